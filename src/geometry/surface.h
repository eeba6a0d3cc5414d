/* surface.h: the visual hull's surface as points, and curves placed on it.
 *
 * The surface is the hull's voxels that have a 6-neighbour outside it (or
 * lie on the grid's edge), each as its centre and an outward unit normal:
 * minus the sum of the offsets of its 26 neighbours that are in the hull
 * (any unit direction where that sum vanishes, as inside a one-voxel wire,
 * marked by a zero normal). Spreading picks points by farthest-point
 * sampling: the first uniformly at random, each next the point farthest
 * from every point picked so far and from the `avoid` points (ties to the
 * lowest index), so the result depends on the rng alone. */
#ifndef WS_SURFACE_H
#define WS_SURFACE_H
#include "geometry/hull.h"
#include "io/scene.h"
#include "nn/base/rng.h"
#include "render/curves.h"

#define WS_HULL_INIT_RESOLUTION 96

typedef struct {
    int n;
    double *p;      /* n x 3 */
    double *normal; /* n x 3, unit or zero */
} ws_hull_surface;

int ws_hull_surface_make(const ws_hull *h, ws_hull_surface *s, ws_status *st);
void ws_hull_surface_free(ws_hull_surface *s);

/* The visual hull of a loaded scene's split and its surface, carved once
 * and shared by whatever needs them (a fit's initial curves, its respawn
 * and its hidden-line removal). */
typedef struct ws_scene_hull {
    ws_hull hull;
    ws_hull_surface surface;
} ws_scene_hull;

/* The hull of split `split` of a loaded scene, carved from its views'
 * silhouettes sil (one per view, silhouette.h) with the default tolerance
 * at `resolution`, and its surface. Fails with WS_EINPUT when the hull is
 * empty. */
int ws_scene_hull_make(const ws_scene *scene, int split, const ws_silhouette *sil, int resolution,
                       ws_scene_hull *out, ws_status *st);
void ws_scene_hull_free(ws_scene_hull *h);

/* picked[0..k): k <= s->n surface points by farthest-point sampling (see
 * above); *spacing: the distance of the last one picked to the others. */
int ws_hull_surface_spread(const ws_hull_surface *s, const double *avoid, int navoid, int k,
                           ws_rng *rng, int *picked, double *spacing, ws_status *st);

/* n curves on the surface: spread points, each the middle of a straight
 * stroke tangent to the surface (a uniform direction orthogonal to the
 * normal) of length max(length, spacing / 2), so that the strokes start
 * neither as dots nor overlapping. Allocates c. */
int ws_curves_init_hull(ws_curves *c, const ws_hull_surface *s, int n, double length,
                        double thickness, double overlap, ws_rng *rng, ws_status *st);

#endif
