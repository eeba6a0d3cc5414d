/* surface.h: the visual hull's surface as points, and curves placed on it.
 *
 * The surface is the hull's voxels that have a 6-neighbour outside it (or
 * lie on the grid's edge), each as its centre and an outward unit normal:
 * minus the sum of the offsets of its 26 neighbours that are in the hull
 * (any unit direction where that sum vanishes, as inside a one-voxel wire,
 * marked by a zero normal), and how squarely the cameras see it: its
 * facing, the largest cosine between its normal and the direction from it
 * to a camera that has it in its frame (1 for a zero normal, -1 when no
 * camera has it in its frame).
 *
 * Spreading picks placeable points by farthest-point sampling: the first
 * uniformly at random (drawn among all points until a placeable one comes,
 * so a first draw that is placeable is what it was without the rule), each
 * next the placeable point farthest from every point picked so far and
 * from the `avoid` points (ties to the lowest index), so the result
 * depends on the rng alone and a spread whose picks were all placeable is
 * unchanged. The other points neither take a pick nor keep picks away:
 * edges border them (a solid's lower rim), and strokes must start near
 * those too. A point is placeable when its facing is at least
 * WS_SURFACE_MIN_FACING (every point is when none is): no camera sees the
 * others within 60 degrees of their normal, so a stroke there lies on or
 * near the object's outline in the few views that see it and behind the
 * object in the rest, and nothing tells its depth (the hull's underside,
 * which the cameras above it never carve, and faces turned down from every
 * camera; docs/METHOD.md section 7 has the measurements). */
#ifndef WS_SURFACE_H
#define WS_SURFACE_H
#include "geometry/hull.h"
#include "io/scene.h"
#include "nn/base/rng.h"
#include "render/curves.h"

#define WS_HULL_INIT_RESOLUTION 96
#define WS_SURFACE_MIN_FACING 0.5 /* cos 60 degrees */

typedef struct {
    int n;
    double *p;      /* n x 3 */
    double *normal; /* n x 3, unit or zero */
    double *facing; /* n */
    int placeable;  /* points whose facing is at least WS_SURFACE_MIN_FACING */
} ws_hull_surface;

/* The surface of h, its facing seen from the nviews views. */
int ws_hull_surface_make(const ws_hull *h, const ws_hull_view *views, int nviews, ws_hull_surface *s,
                         ws_status *st);
void ws_hull_surface_free(ws_hull_surface *s);

/* The surface seen from cam, z-buffered (z, nearest: cam's height x
 * width): each point drawn as a disc of radius rho (world units) at its
 * depth, at least half a pixel, covering the pixels whose centres it holds.
 * z is the nearest disc's depth (+inf where none falls) and nearest its
 * point's index (-1 there); far, unless NULL, the farthest disc's depth
 * (-inf there). */
void ws_hull_surface_depth(const ws_hull_surface *s, const ws_camera *cam, double rho, float *z, int *nearest,
                           float *far);

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

/* How many points spreading chooses from: s->placeable, or s->n when that
 * is 0. */
int ws_hull_surface_candidates(const ws_hull_surface *s);

/* Farthest-point sampling one point at a time, for a caller that adds the
 * points to avoid as it goes (the respawn): nearest (s->n) holds each
 * surface point's squared distance to the points so far (INFINITY for
 * none); _nearer lowers it for n more points, _farthest is the candidate
 * with the largest (the first among equals). */
void ws_hull_surface_nearer(const ws_hull_surface *s, const double *points, int n, double *nearest);
int ws_hull_surface_farthest(const ws_hull_surface *s, const double *nearest);

/* picked[0..k): k <= ws_hull_surface_candidates(s) surface points by
 * farthest-point sampling (see above); *spacing: the distance of the last
 * one picked to the others. */
int ws_hull_surface_spread(const ws_hull_surface *s, const double *avoid, int navoid, int k,
                           ws_rng *rng, int *picked, double *spacing, ws_status *st);

/* n curves on the surface: spread points (as many as there are
 * candidates, up to n, each taken in turn), each the middle of a straight
 * stroke tangent to the surface (a uniform direction orthogonal to the
 * normal) of length max(length, spacing / 2), so that the strokes start
 * neither as dots nor overlapping. Allocates c. */
int ws_curves_init_hull(ws_curves *c, const ws_hull_surface *s, int n, double length,
                        double thickness, double overlap, ws_rng *rng, ws_status *st);

#endif
