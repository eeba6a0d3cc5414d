/* respawn.h: curves that do not earn their place are moved to the photos'
 * edges that the sketch leaves uncovered.
 *
 * Every --respawn-every steps (300; 0 = never), up to three quarters of the
 * schedule's steps (epochs x batches x inner steps, so a --max-steps given
 * at a resume does not move it), a curve is idle when
 * - it has collapsed: the bounding box of its Gaussian centres has a
 *   diagonal below WS_COLLAPSED_EXTENT x the thickness (a dot, or a
 *   "hairpin" whose ends met; no curve that draws a line is that small);
 * - or it draws no edge: of the projections of its Gaussians into the
 *   training views that fall in the frame, fewer than WS_EDGE_SHARE lie
 *   within WS_DRAWS_EDGE_PX of an edge pixel (below) (a stroke across a
 *   face; the ground-truth edges of the solid scenes score 0.23 to 1, the
 *   lowest being edges that the cameras see only through a hole);
 * - or more than half of its Gaussians are outside the silhouettes: a
 *   Gaussian is outside when, in more than half of the training views that
 *   see it, the silhouette's distance map at its projected centre exceeds
 *   its footprint (f r / d) by more than 1.42 px (as the hull's test,
 *   hull.h);
 * - or it has had no gradient: Adam's second moment of every one of its
 *   control point coordinates is 0 (no step ever pulled it).
 *
 * Where an idle curve goes. An edge pixel of a training view is a pixel of
 * its line target (objective/line_target.h) >= 1/2; its distance to the
 * sketch is the distance, in pixels, from it to the nearest pixel holding
 * the projected centre of a Gaussian of a curve that stays (or of a stroke
 * already placed). Idle curves are placed one after another, each on the
 * farthest edge pixel of all views (the first in view, row, column order
 * among equals), when that distance is at least WS_UNCOVERED_PX:
 * - depth: along the pixel's ray, from where it enters the visual hull's
 *   grid to where it leaves it, every half voxel inside the hull is a
 *   candidate; each scores the other training views in which its
 *   projection lies within WS_ON_EDGE_PX of an edge pixel (the views agree
 *   where the edge truly is: a triangulation by all of them); the best
 *   score wins, the nearest among equals. A ray that meets no hull voxel
 *   leaves that pixel out and the next farthest is taken;
 * - direction: the principal axis of the edge pixels within 3 px of it;
 * - extent: from the pixel along that axis both ways, while the point stays
 *   within WS_ON_EDGE_PX of an edge pixel, at most the pixel's distance to
 *   the sketch (beyond it the edge may be drawn) and half of the stroke
 *   length below;
 * - the stroke: straight between its two ends, each found like the
 *   middle on its own ray, among the depths within 3 x its image offset
 *   (back-projected) of the middle's (the middle's depth where none is in
 *   the hull), at least 2 x WS_COLLAPSED_EXTENT thicknesses long.
 * When no edge pixel is that far from the sketch (every edge is drawn) the
 * curve goes, as before, to the placeable point (surface.h) of the
 * visual hull's surface farthest from every Gaussian of the curves that
 * stay (and of those already moved), as a stroke of length max(--length,
 * half the spacing of the initial spread) tangent to it along the axis
 * least aligned with the surface normal. Either way its Adam moments are
 * reset. No random draw is made, so a run and its resumption move the
 * same curves.
 *
 * At the end of a fit (with respawning on), the curves that have collapsed
 * or draw no edge are retired: left out of every output (fit_outputs.h). */
#ifndef WS_RESPAWN_H
#define WS_RESPAWN_H
#include "fit/adam.h"
#include "geometry/surface.h"
#include "io/scene.h"
#include "objective/view_targets.h"
#include "render/curves.h"

#define WS_COLLAPSED_EXTENT 3.0 /* thicknesses */
#define WS_UNCOVERED_PX 3.0
#define WS_ON_EDGE_PX 1.5
#define WS_DRAWS_EDGE_PX 2.0
#define WS_EDGE_SHARE 0.2

typedef struct ws_respawn ws_respawn;

/* From the training views of a loaded scene: their silhouettes and line
 * targets, read from (and made by) `targets`, and their hull; both
 * borrowed: they must outlive it. */
int ws_respawn_create(ws_respawn **out, const ws_scene *scene, ws_view_targets *targets,
                      const ws_scene_hull *hull, int n_curves,
                      double length, ws_status *st);
void ws_respawn_free(ws_respawn *r);

/* Moves the idle curves of c (see above), resets their moments in adam;
 * *moved: how many. */
int ws_respawn_step(ws_respawn *r, ws_curves *c, ws_adam *adam, int *moved, ws_status *st);

/* retire[ci] (c->n): whether curve ci of a finished fit is left out of its
 * outputs: it has collapsed or draws no edge (see above). */
int ws_respawn_retire(const ws_respawn *r, const ws_curves *c, int *retire, ws_status *st);

#endif
