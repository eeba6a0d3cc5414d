/* hull_outline.h: which pixels of a view the visual hull covers, exactly:
 * an image-based visual hull (Matusik et al. 2000) for the pixels where a
 * voxel hull's outline is too rough.
 *
 * The voxel hull (hull.h) is conservative: a voxel stays while its whole
 * ball may touch the object, so its outline in a view lies a pixel or two
 * outside the object's. Here the ray through a pixel's centre is tested
 * against the silhouettes themselves. Each view's silhouette becomes a
 * signed distance to its edge, in pixels, at every pixel centre:
 *     sd = dist to the nearest background pixel centre - 1/2, negated, on
 *          an object pixel; dist to the nearest object pixel centre - 1/2
 *          on a background pixel; plus the silhouette's edge_inset
 * so that sd, interpolated bilinearly between pixel centres, is 0 on the
 * edges between object and background pixels (or, for a silhouette
 * thresholded from a photo, on the outermost object pixels' centres:
 * silhouette.h) and changes by at most sqrt 2 per pixel. A point is outside view k by s_k = sd at its
 * projection (outside the frame: the distance to the frame plus 1/2, or
 * no say for a silhouette that touches the frame, as the voxel hull has
 * none; behind the camera: no say), and in the hull when at most
 * `tolerance` views have s_k > 0 (the voxel hull's tolerance, so that the
 * same few bad masks carve nothing).
 *
 * A ray is followed from where it enters a box that holds the hull (or
 * the nearest depth it may meet the hull at) by sphere tracing: with s_k and the speed v_k (pixels per unit of the ray's
 * parameter) of the point's projection in every view, the point stays
 * outside while more than `tolerance` views still see it outside, which
 * no view's s_k can stop doing within s_k / (sqrt 2 v_k): the step is
 * the (tolerance + 1)-th largest of those, times WS_OUTLINE_STEP_SHARE
 * (the speed changes along the step with perspective), and at least
 * WS_OUTLINE_MIN_STEP_PX pixels in the fastest view. A ray that reaches
 * the box's far side (or the farthest depth it may meet the hull at)
 * misses. A hull part thinner than the smallest step
 * along the ray can be missed; at a tenth of a pixel that is below what
 * the silhouettes resolve. Deterministic (each pixel alone). */
#ifndef WS_HULL_OUTLINE_H
#define WS_HULL_OUTLINE_H
#include <stdint.h>
#include "geometry/hull.h"
#include "nn/base/status.h"

#define WS_OUTLINE_STEP_SHARE 0.8
#define WS_OUTLINE_MIN_STEP_PX 0.1
#define WS_OUTLINE_MAX_STEPS 20000

typedef struct {
    const ws_hull_view *views; /* borrowed */
    int nviews, tolerance;
    float **sd;           /* nviews maps, each its view's height x width */
    double lo[3], hi[3];  /* a box that holds the hull */
} ws_hull_outline;

/* The signed distances of the views' silhouettes; lo, hi: a world box
 * that holds the hull (a voxel hull's grid: ws_hull_outline_box). Fails
 * when out of memory, or with WS_EINTERNAL on a tolerance out of [0, 250]
 * or an empty box. */
int ws_hull_outline_init(ws_hull_outline *o, const ws_hull_view *views, int nviews, int tolerance,
                         const double lo[3], const double hi[3], ws_status *st);
void ws_hull_outline_free(ws_hull_outline *o);

/* The box of h's grid, where every voxel it keeps lies. */
void ws_hull_outline_box(const ws_hull *h, double lo[3], double hi[3]);

/* covered[p] = whether the ray through pixel p's centre meets the hull,
 * for every pixel p with band[p] set (cam's height x width each); the
 * other pixels are left as they are. near, far (or NULL: no bound): the
 * depths between which the ray can meet the hull at each pixel (a voxel
 * hull's nearest and farthest surface there, widened by its voxels), so
 * that a ray grazing the hull is not followed beyond them (a third of the
 * time of a drawing, measured on the rose). Fails only when out of
 * memory. */
int ws_hull_outline_cover(const ws_hull_outline *o, const ws_camera *cam, const uint8_t *band, const float *near,
                          const float *far, uint8_t *covered, ws_status *st);

#endif
