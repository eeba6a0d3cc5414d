/* drawing_score.h: how well a sketch reads as a line drawing, scored in 2D
 * on the test views against reference lines (io/ref_lines.h: silhouette,
 * inner occluding contours, creases, 1 px wide).
 *
 * For one view of W x H pixels, with the sketch's render (io/turntable.h:
 * black strokes on white):
 *   S   = the pixels with grey < 128, thinned to 1 px (render/skeleton.h);
 *   R   = the reference line pixels, C those of silhouette or inner contour;
 *   M   = the object's pixels (any part but background);
 *   d_X = the Euclidean distance to the nearest pixel of X (render/distance.h);
 *   tau = WS_DRAWING_TAU[k] x sqrt(W^2 + H^2) (1% and 0.5% of the diagonal;
 *         3.17 and 1.58 px at 224 x 224);
 *   precision_k      = |{s in S: d_R(s) <= tau}| / |S|
 *   recall_k         = |{r in R: d_S(r) <= tau}| / |R|
 *   fscore_k         = 2 P R / (P + R), 0 when P = R = 0
 *   contour_recall_k = |{c in C: d_S(c) <= tau}| / |C|
 *   scribble_k       = |{s in S in M: d_R(s) > tau}| / |S|  (drawn inside the
 *                      object, away from every line: texture, tangles)
 *   overdraw         = |S| / |R|.
 * A sketch that draws nothing in a view scores precision, recall, F and
 * scribble 0 there. The scene's score is the mean over its views that have
 * reference lines (those without any, an object out of frame, are left
 * out; contour recall over those with an outline). Deterministic. */
#ifndef WS_DRAWING_SCORE_H
#define WS_DRAWING_SCORE_H
#include <stdint.h>
#include <stdio.h>
#include "io/scene.h"
#include "io/turntable.h"
#include "render/curves.h"
#include "nn/base/status.h"

#define WS_DRAWING_NTAU 2 /* the distances tau: 1% and 0.5% of the image diagonal */

typedef struct {
    int views, contour_views; /* views scored; of them, with an outline */
    double precision[WS_DRAWING_NTAU], recall[WS_DRAWING_NTAU], fscore[WS_DRAWING_NTAU];
    double contour_recall[WS_DRAWING_NTAU], scribble[WS_DRAWING_NTAU];
    double overdraw;
} ws_drawing_score;

/* One view: gray (H x W, the sketch render), part (H x W, ws_line_part).
 * s->views = 0 when the view has no reference line (s is then zero),
 * contour_views = 0 when it has no outline. Fails only when out of memory. */
int ws_drawing_score_view(const unsigned char *gray, const uint8_t *part, int W, int H, ws_drawing_score *s,
                          ws_status *st);

/* The sketch c rendered from every view of split (turned into a drawing by
 * render(ctx, ...) unless render is NULL) and scored against the reference
 * lines lines_dir/NAME.png, NAME_parts.png of each (a view's files must
 * exist and have the scene's size). Fails (naming the file) on a missing
 * or wrong file, or when no view has a line. */
int ws_drawing_score_split(const ws_split *split, int W, int H, const ws_curves *c, const char *lines_dir,
                           ws_drawing_render_fn render, void *ctx, ws_drawing_score *s, ws_status *st);

/* SCENE/lines/SPLIT into dir (WS_PATH_MAX bytes) when that directory
 * exists (returns 1), else "" (returns 0). */
int ws_drawing_lines_dir(const char *scene_dir, const char *split_name, char *dir);

/* Whether the reference lines in lines_dir are W x H pixels (those of the
 * split's first view; 1 when that file cannot be read, which scoring then
 * names): lines drawn at a scene's own size cannot score its views at
 * another --size. 0 with why (size bytes) saying so. */
int ws_drawing_lines_match(const char *lines_dir, const ws_split *split, int W, int H, char *why, size_t size);

/* Writes `"KEY": {"views": ..., "overdraw": ..., "precision_1": ...,
 * "recall_1", "fscore_1", "contour_recall_1", "scribble_1", then the same
 * with suffix 0.5}` for metrics.json and eval. */
void ws_drawing_score_json(FILE *fp, const char *key, const ws_drawing_score *s);

#endif
