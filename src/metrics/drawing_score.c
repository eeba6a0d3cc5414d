/* drawing_score.c: the 2D drawing score (see drawing_score.h). Sums run
 * serially in pixel and view order, so the score does not depend on the
 * thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "base/paths.h"
#include "io/image.h"
#include "io/ref_lines.h"
#include "io/turntable.h"
#include "metrics/drawing_score.h"
#include "render/distance.h"
#include "render/skeleton.h"

/* the distances: 0.01 and 0.005 of the diagonal, named in percent */
static const double drawing_tau[WS_DRAWING_NTAU] = {0.01, 0.005};
static const char *const drawing_tau_name[WS_DRAWING_NTAU] = {"1", "0.5"};

static double ratio(size_t a, size_t b) { return b ? (double)a / (double)b : 0; }

int ws_drawing_score_view(const unsigned char *gray, const uint8_t *part, int W, int H, ws_drawing_score *s,
                          ws_status *st) {
    const size_t n = (size_t)W * H;
    memset(s, 0, sizeof *s);
    uint8_t *sketch = ws_malloc(n, "drawing score", st);
    uint8_t *lines = sketch ? ws_malloc(n, "drawing score", st) : NULL;
    float *to_lines = lines ? ws_malloc(n * sizeof *to_lines, "drawing score", st) : NULL;
    float *to_sketch = to_lines ? ws_malloc(n * sizeof *to_sketch, "drawing score", st) : NULL;
    int rc = to_sketch ? WS_OK : st->code;
    size_t ns = 0, nr = 0, nc = 0;
    if (!rc) {
        for (size_t p = 0; p < n; p++) {
            sketch[p] = gray[p] < 128;
            lines[p] = (uint8_t)ws_part_is_line(part[p]);
            nr += lines[p];
            nc += ws_part_is_outline(part[p]);
        }
        rc = ws_skeleton_thin(sketch, W, H, st);
    }
    if (!rc) rc = ws_distance_map(lines, W, H, to_lines, st);
    if (!rc) rc = ws_distance_map(sketch, W, H, to_sketch, st);
    if (!rc && nr) {
        for (size_t p = 0; p < n; p++) ns += sketch[p];
        const double diagonal = sqrt((double)W * W + (double)H * H);
        for (int k = 0; k < WS_DRAWING_NTAU; k++) {
            const double tau = drawing_tau[k] * diagonal;
            size_t near = 0, scribble = 0, found = 0, found_outline = 0;
            for (size_t p = 0; p < n; p++) {
                if (sketch[p] && to_lines[p] <= tau) near++;
                if (sketch[p] && part[p] != WS_PART_BACKGROUND && to_lines[p] > tau) scribble++;
                if (lines[p] && to_sketch[p] <= tau) {
                    found++;
                    found_outline += ws_part_is_outline(part[p]);
                }
            }
            double P = ratio(near, ns), R = ratio(found, nr);
            s->precision[k] = P;
            s->recall[k] = R;
            s->fscore[k] = P + R > 0 ? 2 * P * R / (P + R) : 0;
            s->contour_recall[k] = ratio(found_outline, nc);
            s->scribble[k] = ratio(scribble, ns);
        }
        s->overdraw = ratio(ns, nr);
        s->views = 1;
        s->contour_views = nc > 0;
    }
    free(sketch);
    free(lines);
    free(to_lines);
    free(to_sketch);
    return rc;
}

int ws_drawing_score_split(const ws_split *split, int W, int H, const ws_curves *c, const char *lines_dir,
                           ws_drawing_render_fn render, void *ctx, ws_drawing_score *s, ws_status *st) {
    memset(s, 0, sizeof *s);
    ws_sketch_renderer r;
    if (ws_sketch_renderer_init(&r, W, H, st)) return st->code;
    uint8_t *part = ws_malloc((size_t)W * H, "reference lines", st);
    unsigned char *drawing = part && render ? ws_malloc((size_t)W * H, "a drawing", st) : NULL;
    int rc = part && (drawing || !render) ? WS_OK : st->code;
    for (int v = 0; v < split->n && !rc; v++) {
        const ws_view *view = &split->views[v];
        ws_drawing_score one;
        rc = ws_ref_lines_read(lines_dir, view->name, W, H, part, st);
        if (!rc) rc = ws_sketch_render(&r, c, &view->cam, st);
        if (!rc && render) rc = render(ctx, &view->cam, r.gray, drawing, st);
        if (!rc) rc = ws_drawing_score_view(render ? drawing : r.gray, part, W, H, &one, st);
        if (rc || !one.views) continue;
        s->views++;
        s->contour_views += one.contour_views;
        s->overdraw += one.overdraw;
        for (int k = 0; k < WS_DRAWING_NTAU; k++) {
            s->precision[k] += one.precision[k];
            s->recall[k] += one.recall[k];
            s->fscore[k] += one.fscore[k];
            s->contour_recall[k] += one.contour_recall[k];
            s->scribble[k] += one.scribble[k];
        }
    }
    if (!rc && !s->views) rc = ws_fail(st, WS_EINPUT, "%s: no view has a reference line", lines_dir);
    if (!rc) {
        s->overdraw /= s->views;
        for (int k = 0; k < WS_DRAWING_NTAU; k++) {
            s->precision[k] /= s->views;
            s->recall[k] /= s->views;
            s->fscore[k] /= s->views;
            s->scribble[k] /= s->views;
            s->contour_recall[k] = s->contour_views ? s->contour_recall[k] / s->contour_views : 0;
        }
    }
    free(part);
    free(drawing);
    ws_sketch_renderer_free(&r);
    return rc;
}

int ws_drawing_lines_match(const char *lines_dir, const ws_split *split, int W, int H, char *why, size_t size) {
    if (split->n == 0) return 1;
    char path[WS_PATH_MAX + 80];
    snprintf(path, sizeof path, "%s/%s.png", lines_dir, split->views[0].name);
    const float black[3] = {0, 0, 0};
    ws_image img = {0};
    ws_status st;
    ws_status_clear(&st);
    if (ws_image_read(path, 0, 0, black, &img, &st)) return 1; /* the score names what is wrong with it */
    int match = img.width == W && img.height == H;
    if (!match)
        snprintf(why, size, "%s: the reference lines are %d x %d pixels, the views %d x %d (--size)", lines_dir,
                 img.width, img.height, W, H);
    ws_image_free(&img);
    return match;
}

int ws_drawing_lines_dir(const char *scene_dir, const char *split_name, char *dir) {
    struct stat sb;
    snprintf(dir, WS_PATH_MAX, "%s/lines/%s", scene_dir, split_name);
    if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode)) return 1;
    dir[0] = '\0';
    return 0;
}

void ws_drawing_score_json(FILE *fp, const char *key, const ws_drawing_score *s) {
    fprintf(fp, "\"%s\": {\"views\": %d, \"overdraw\": %.9g", key, s->views, s->overdraw);
    for (int k = 0; k < WS_DRAWING_NTAU; k++) {
        const char *t = drawing_tau_name[k];
        fprintf(fp, ", \"precision_%s\": %.9g, \"recall_%s\": %.9g, \"fscore_%s\": %.9g, "
                "\"contour_recall_%s\": %.9g, \"scribble_%s\": %.9g",
                t, s->precision[k], t, s->recall[k], t, s->fscore[k], t, s->contour_recall[k], t, s->scribble[k]);
    }
    fputc('}', fp);
}
