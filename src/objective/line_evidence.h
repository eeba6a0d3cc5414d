/* line_evidence.h: where a view's photo edges have geometric support from
 * the training views' visual hull (geometry/surface.h), so that the line
 * target (line_target.h) keeps the outline and feature lines of a
 * textured object and leaves its texture alone.
 *
 * A photo edge inside the silhouette is a line of the drawing where the
 * object's shape changes there: an inner occluding contour (the depth
 * jumps) or a crease (the normal turns sharply). Texture edges have
 * neither. The hull carries both, roughly: it is the object's shape seen
 * from the training views' silhouettes, proud of it by a voxel or so.
 *   crease voxels  surface voxels whose neighbourhood (the surface voxels
 *                  within WS_EVIDENCE_CREASE_REACH voxels) is not flat:
 *                  its surface variation lambda_0 / (lambda_0 + lambda_1 +
 *                  lambda_2), lambda_0 the smallest eigenvalue of the
 *                  covariance of their centres, exceeds
 *                  WS_EVIDENCE_CREASE_VARIATION (0 on a plane; a voxel
 *                  staircase gives about 0.02, a 90 degree edge about 0.1,
 *                  a smooth bend of radius 10 voxels about 0.02). The
 *                  hull's own normals (26-neighbour sums) are too rough on
 *                  a slanted face to tell a bend from a staircase;
 *   Z, K (H x W)   the surface voxels z-buffered as discs (radius
 *                  max(1/2, f rho / d) px, rho = voxel sqrt(3) / 2, as the
 *                  hidden lines draw them), keeping the nearest voxel's
 *                  depth and whether it is a crease voxel;
 *   support        pixels with K set, and pixels whose depth Z is smaller
 *                  than a 4-neighbour's by more than
 *                  WS_EVIDENCE_DEPTH_JUMP of it (the near side of a hull
 *                  contour), grown by WS_EVIDENCE_REACH_PX pixels (the hull
 *                  stands proud of the object, so its lines lie off the
 *                  photo's by about that).
 * Deterministic; views can be asked in any order. */
#ifndef WS_LINE_EVIDENCE_H
#define WS_LINE_EVIDENCE_H
#include <stdint.h>
#include "geometry/hull_outline.h"
#include "geometry/surface.h"
#include "render/camera.h"
#include "nn/base/status.h"

#define WS_EVIDENCE_CREASE_VARIATION 0.03
#define WS_EVIDENCE_CREASE_REACH 3    /* voxels */
#define WS_EVIDENCE_DEPTH_JUMP 0.02
#define WS_EVIDENCE_REACH_PX 3.0
#define WS_DRAWING_HULL_RESOLUTION 160 /* voxels along the hull's longest side */
/* pixels: the voxel hull's excess over the object is mostly its carving's
 * pixel slack (geometry/hull.h: 1.42 px) and the discs it is drawn with,
 * 3 to 4 px, not a share of the image */
#define WS_DRAWING_BAND_PX 6.0
#define WS_DRAWING_CURVE_MARGIN_PX 5.0
/* the drawing keeps curves nearer the hull's lines than the line target
 * does (WS_EVIDENCE_REACH_PX): its outline is exact now, and a curve 3 px
 * off a line is off it at 0.5% of the diagonal */
#define WS_DRAWING_SUPPORT_PX 2.0
#define WS_DRAWING_THIN_PX 2.0
#define WS_DRAWING_THIN_EDGE_PX 1.5 /* a thin part's curve is drawn this far beyond its pixels */
#define WS_EVIDENCE_OUTLINE_PX 2.5 /* line_target.h: the outline band, always kept */

typedef struct ws_line_evidence {
    const ws_scene_hull *hull; /* borrowed */
    uint8_t *crease;           /* hull->surface.n: 1 = a crease voxel */
} ws_line_evidence;

/* Flags the hull's crease voxels. Fails only when out of memory. */
int ws_line_evidence_init(ws_line_evidence *e, const ws_scene_hull *hull, ws_status *st);
void ws_line_evidence_free(ws_line_evidence *e);

/* support (cam->height x cam->width): 1 where a photo edge has the hull's
 * support in this view, else 0. */
int ws_line_evidence_view(const ws_line_evidence *e, const ws_camera *cam, uint8_t *support, ws_status *st);

/* The hull a drawing is made with (ws_drawing_hull_render): the training
 * views' visual hull carved at WS_DRAWING_HULL_RESOLUTION (finer than a
 * fit's, so that its creases and contours lie within a pixel or two of the
 * object's) from their silhouettes, its creases, and the silhouettes for
 * the exact outline. */
typedef struct {
    ws_scene_hull hull;
    ws_line_evidence evidence;
    int nviews;
    ws_silhouette *sil;    /* the training views' silhouettes */
    ws_hull_view *views;   /* their cameras and silhouettes */
    ws_hull_outline outline;
} ws_drawing_hull;

/* Needs the scene's photos loaded (the silhouettes are made here). Fails
 * as ws_scene_hull_make does, and with WS_EINPUT when the training views
 * have no usable silhouette (geometry/check.h): their drawing is then the
 * curves alone. */
int ws_drawing_hull_make(ws_drawing_hull *d, const ws_scene *scene, ws_status *st);
void ws_drawing_hull_free(ws_drawing_hull *d);

/* The drawing's two layers apart, from d's evidence (H x W each, for a
 * vector drawing: io/export.h): lines = 1 on the outline and contour
 * pixels, keep = 1 where the curves are drawn. */
int ws_drawing_hull_layers(const ws_drawing_hull *d, const ws_camera *cam, uint8_t *lines, uint8_t *keep,
                           ws_status *st);

/* The drawing a user gets of a view (line_evidence.c: draw_view) from
 * d's evidence, with the signature of a
 * drawing score's renderer (metrics/drawing_score.h); ctx: a ws_drawing_hull. */
int ws_drawing_hull_render(void *ctx, const ws_camera *cam, const unsigned char *curves, unsigned char *drawing,
                           ws_status *st);

#endif
