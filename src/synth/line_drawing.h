/* line_drawing.h: the reference line drawing of a rendered view, from what
 * the renderer knows exactly about each pixel (its geometry buffer), for
 * the drawing score (metrics/drawing_score.h; the file format is
 * io/ref_lines.h). The rules are those of the shared scenes' lines
 * (issue 23), made from their world-position renders:
 *   mask       the pixels the object covers more than half of;
 *   silhouette mask pixels with a 4-neighbour outside the mask;
 *   contour    (inner occluding) mask pixels p with a 4-neighbour q in the
 *              mask that lies farther by more than WS_LINE_DEPTH_JUMP of
 *              p's depth along the ray: p occludes q;
 *   crease     mask pixels p with a 4-neighbour q, no depth jump between
 *              them, whose normals differ by more than WS_LINE_CREASE_ANGLE
 *              while each side is flat (p's normal within WS_LINE_FLAT_ANGLE
 *              of the pixel beyond p, away from q; q's of the pixel beyond
 *              q): a sharp edge, not a smooth surface seen at a slant;
 * then (one pixel one kind, in this order of precedence) the lines are
 * thinned to 1 px (render/skeleton.h) and 8-connected specks of fewer than
 * WS_LINE_MIN_SPECK pixels dropped. */
#ifndef WS_LINE_DRAWING_H
#define WS_LINE_DRAWING_H
#include <stdint.h>
#include "io/image.h"
#include "render/camera.h"
#include "nn/base/status.h"

#define WS_LINE_DEPTH_JUMP 0.02
#define WS_LINE_CREASE_ANGLE 60.0 /* degrees */
#define WS_LINE_FLAT_ANGLE 30.0   /* degrees */
#define WS_LINE_MIN_SPECK 5

/* Rows of pixels the synthetic renderers (solids.h, synth.h) trace at a
 * time: their supersampled buffers (depth, shading and normal of each
 * fine sample) hold these rows, not the whole frame, whose fine samples
 * run to hundreds of millions for a phone-sized canvas through a lens. */
#define WS_SYNTH_BAND_ROWS 16

/* What a renderer knows of each pixel of one view (all H x W): */
typedef struct {
    int width, height;
    float *coverage; /* share of the pixel's rays that hit the object */
    float *depth;    /* along the ray through the pixel's centre (INFINITY: a miss) */
    float *normal;   /* 3 x H x W: unit world normal there (0 on a miss) */
} ws_geometry_buffer;

int ws_geometry_buffer_alloc(ws_geometry_buffer *g, int width, int height, ws_status *st);
/* Pixel (i, j): its coverage, the depth of its centre's ray (INFINITY: a
 * miss) and the unit normal there in cam's camera space (read only on a
 * hit), stored in world space. */
void ws_geometry_buffer_set(ws_geometry_buffer *g, const ws_camera *cam, int i, int j, float coverage, double depth,
                            const float n[3]);
void ws_geometry_buffer_free(ws_geometry_buffer *g);

/* Pixel rows [top, top + rows) of img (3 x H x W) and of g (or NULL) from
 * a band of ss x ss rays a pixel (ss odd; ray row (i - top) ss + a and
 * column j ss + b of W ss are pixel (i, j)'s): each ray's depth (INFINITY
 * where it met nothing), shade (0 there) and, with g, camera-space normal
 * (3 a ray). A pixel is colour times its rays' summed shade plus the
 * background times the rays that met nothing, over ss^2; g gets the share
 * of rays that met the object and the middle ray's depth and normal. Both
 * renderers (solids.h, synth.h) end each band with it. */
void ws_synth_resolve_rows(const double *depth, const float *shade, const float *normal, int ss, int top, int rows,
                           const float colour[3], const ws_image *background, const ws_camera *cam, ws_image *img,
                           ws_geometry_buffer *g);

/* part: H x W ws_line_part values (io/ref_lines.h). Fails only when out of
 * memory. */
int ws_line_drawing(const ws_geometry_buffer *g, uint8_t *part, ws_status *st);

#endif
