/* distance.h: the Euclidean distance transform of a set of pixels: for
 * every pixel centre, the distance in pixels to the nearest pixel centre of
 * the set (0 on it; INFINITY everywhere when the set is empty), exact
 * (Felzenszwalb and Huttenlocher's lower envelope of parabolas, rows then
 * columns). The silhouettes' distance maps (silhouette.h) and the thin
 * parts of the line loss's target (objective/line_target.h) use it. */
#ifndef WS_DISTANCE_H
#define WS_DISTANCE_H
#include <stdint.h>
#include "nn/base/status.h"

/* set: H x W, nonzero = in the set; distance: H x W, overwritten. Fails
 * only when out of memory. */
int ws_distance_map(const uint8_t *set, int W, int H, float *distance, ws_status *st);

#endif
