/* respawn.h: curves that do not earn their place are moved to where the
 * sketch is thinnest.
 *
 * Every --respawn-every steps (300; 0 = never), up to three quarters of the
 * schedule's steps (epochs x batches x inner steps, so a --max-steps given
 * at a resume does not move it), a curve is idle when
 * - more than half of its Gaussians are outside the silhouettes: a Gaussian
 *   is outside when, in more than half of the training views that see it,
 *   the silhouette's distance map at its projected centre exceeds its
 *   footprint (f r / d) by more than 1.42 px (as the hull's test, hull.h);
 * - or it has had no gradient: Adam's second moment of every one of its
 *   control point coordinates is 0 (no step ever pulled it).
 * Each idle curve becomes a short straight stroke, of length
 * max(--length, half the spacing of the initial spread), on the visual
 * hull's surface at the point farthest from every Gaussian of the curves
 * that stay (and of those already moved), tangent to it along the axis
 * least aligned with the surface normal; its Adam moments are reset. No
 * random draw is made, so a run and its resumption move the same curves. */
#ifndef WS_RESPAWN_H
#define WS_RESPAWN_H
#include "fit/adam.h"
#include "io/scene.h"
#include "render/curves.h"

typedef struct ws_respawn ws_respawn;

/* From the training views of a loaded scene (silhouettes, hull surface). */
int ws_respawn_create(ws_respawn **out, const ws_scene *scene, int n_curves, double length,
                      ws_status *st);
void ws_respawn_free(ws_respawn *r);

/* Moves the idle curves of c (see above), resets their moments in adam;
 * *moved: how many. */
int ws_respawn_step(ws_respawn *r, ws_curves *c, ws_adam *adam, int *moved, ws_status *st);

#endif
