/* smooth.h: smooth, textured synthetic objects (`wiresketch scene
 * torus|vase|animal`), the test bed of the drawing score
 * (metrics/drawing_score.h): their lines are view-dependent (silhouette,
 * inner occluding contours) and few, their textures draw many photo edges
 * where a drawing has none.
 *   torus   ring radius 0.55, tube radius 0.2, lying flat (axis +z);
 *           24 stripes across the tube, yellow and blue;
 *   vase    a surface of revolution about +z, 1.2 tall, radius
 *           0.32 + 0.14 sin(4.2 z + 0.9) (foot 0.18, belly 0.46, neck
 *           0.28), flat top and bottom (two rims, creases); terracotta with
 *           dark spots (one per cell of a 0.18 grid, radius 0.06);
 *   animal  a four-legged capsule animal: body, four legs, neck, head and
 *           tail, blended (smooth minimum, 0.06) into one surface; tan with
 *           dark blotches where a value noise exceeds a threshold.
 * Each is a signed distance function (exact or a lower bound), rendered by
 * sphere tracing: albedo(texture at the hit) x (AMBIENT + (1 - AMBIENT)
 * max(0, n.l)), l fixed in world space, as the tubes are lit (synth.h);
 * the background where nothing is hit. The geometry buffer gives every
 * pixel's coverage and its centre ray's depth and normal, from which the
 * scene's reference lines are drawn (line_drawing.h). */
#ifndef WS_SMOOTH_H
#define WS_SMOOTH_H
#include "render/camera.h"
#include "io/image.h"
#include "synth/line_drawing.h"
#include "nn/base/status.h"

typedef struct {
    int kind;         /* which object: 0 torus, 1 vase, 2 animal */
    double center[3]; /* the object's centre (of its bounding box) */
} ws_smooth;

int ws_smooth_exists(const char *name);

/* Fails with WS_EUSAGE for an unknown name. */
int ws_smooth_make(ws_smooth *s, const char *name, const double center[3], ws_status *st);

/* Renders s seen by cam into img (allocated here: 3 x height x width), the
 * average of supersample^2 rays per pixel (supersample odd, so that one
 * ray passes through the pixel's centre); g: NULL, or a buffer of the
 * camera's size to fill. */
int ws_smooth_render(const ws_smooth *s, const ws_camera *cam, int supersample, const float background[3],
                     ws_image *img, ws_geometry_buffer *g, ws_status *st);

#endif
