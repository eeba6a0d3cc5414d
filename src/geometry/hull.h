/* hull.h: the visual hull of a set of views by voxel carving.
 *
 * A voxel (a cube of edge `voxel`, tested as its circumscribed ball of
 * radius rho = voxel sqrt(3) / 2) is seen outside by a view when the ball
 * lies in front of the camera and its projection misses the silhouette:
 * the silhouette distance at the pixel under the projected centre exceeds
 * the ball's projected radius f rho / (d - rho) by more than 1.42 px (half
 * a pixel's diagonal twice: once for the pixel centre the distance is read
 * at, once for the silhouette pixel's own extent), or the centre projects
 * out of the frame farther than that radius, for a view whose silhouette
 * does not touch the frame's edge (one that does may hold more of the
 * object beyond it, so it has no say there). The test is conservative: a
 * voxel that holds any part of the object is never seen outside by a view
 * whose silhouette and camera are right.
 *
 * A tight hull (for measuring, not for holding the object: check.c's
 * field-of-view estimate) tests the voxel's centre against half the ball's
 * projected radius and no pixel slack, so that silhouettes which disagree
 * by a pixel already carve each other: it loses thin parts of a right
 * object, but about equally at every camera error, while a conservative
 * hull hides a disagreement of up to 1.42 px plus a voxel.
 *
 * The hull keeps the voxels seen outside by at most `tolerance` views, so
 * that a few bad masks carve nothing. Carving runs twice: over a cube
 * around the scene centre whose half side is the largest half-width of a
 * view at the centre's depth (times sqrt 2, its half-diagonal) at
 * WS_HULL_COARSE voxels a side, then over the box of what survived (one
 * coarse voxel wider) at `resolution` voxels along its longest side. As
 * the test is conservative, the coarse pass removes nothing the fine one
 * would keep. */
#ifndef WS_HULL_H
#define WS_HULL_H
#include <stdint.h>
#include "geometry/silhouette.h"
#include "render/camera.h"
#include "nn/base/status.h"

#define WS_HULL_COARSE 32

typedef struct {
    const ws_camera *cam;
    const ws_silhouette *sil;
} ws_hull_view;

typedef struct {
    int n[3];          /* voxels along x, y, z; voxel (x, y, z) is outside[(z n1 + y) n0 + x] */
    double origin[3];  /* the corner of voxel (0, 0, 0) */
    double voxel;      /* edge length, world units */
    int tolerance;
    int tight;         /* carved with the tight test (above) */
    uint8_t *outside;  /* views that see the voxel outside, counted up to tolerance + 2 */
    long kept;         /* voxels with outside <= tolerance */
} ws_hull;

/* The default tolerance for n views: n / 20 (5%, rounded down), at most 250. */
int ws_hull_default_tolerance(int nviews);

int ws_hull_carve(const ws_hull_view *views, int nviews, const double center[3], int resolution,
                  int tolerance, int tight, ws_hull *h, ws_status *st);
void ws_hull_free(ws_hull *h);

static inline size_t ws_hull_index(const ws_hull *h, int x, int y, int z) {
    return ((size_t)z * h->n[1] + y) * h->n[0] + x;
}
static inline int ws_hull_in(const ws_hull *h, size_t k) { return h->outside[k] <= h->tolerance; }

/* World centre of voxel (x, y, z). */
void ws_hull_voxel_center(const ws_hull *h, int x, int y, int z, double p[3]);

/* Agreement of every view with the hull: agreement[k] is the share of
 * view k's silhouette covered by the projection of the hull, each voxel
 * drawn as the disc of its inscribed ball (an empty silhouette and an
 * empty projection agree: 1). carved: h was carved from `views`, and view
 * k is judged against the hull of the other views (the voxels seen outside
 * by at most `tolerance` views other than k); 0: views h has not seen
 * (another split's), judged against the whole hull. */
int ws_hull_agreement(const ws_hull_view *views, int nviews, int carved, const ws_hull *h,
                      double *agreement, ws_status *st);

#endif
