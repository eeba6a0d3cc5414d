/* view_spread.h: at most a given number of train views, spread over their
 * directions from a centre, for the steps whose cost or judgement grows
 * with the views (geometry/photo_hull.h, objective/edge_consensus.h).
 *
 * Every view when there are at most `most`; else `most` of them picked
 * farthest-point: the first view, then each time the view whose nearest
 * chosen one (by the angle between their directions from the centre) is
 * farthest, the first among equals; listed in view order. No train view is
 * then farther from its nearest chosen one than the two nearest chosen ones
 * are from each other. Deterministic, and the views of an ordered capture
 * (a video's frames along a path) are taken from all of it, not its
 * beginning. */
#ifndef WS_VIEW_SPREAD_H
#define WS_VIEW_SPREAD_H
#include "io/scene.h"
#include "nn/base/status.h"

/* e: the unit direction from centre to the camera of cam (0 when they
 * meet): a view's direction here and in the photo hull's pairing. */
void ws_view_direction(const ws_camera *cam, const double centre[3], double e[3]);

/* views (room for min(train->n, most)), *n: the chosen views. Fails only
 * when out of memory. */
int ws_view_spread(const ws_split *train, const double centre[3], int most, const ws_view **views, int *n,
                   ws_status *st);

#endif
