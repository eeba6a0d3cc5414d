/* skeleton.h: a set of pixels thinned to lines one pixel wide (Zhang and
 * Suen's parallel thinning, CACM 27(3), 1984), the way a drawing's strokes
 * and the reference lines it is scored against are reduced to their
 * centre lines (metrics/drawing_score.h, synth/ref_lines.h).
 *
 * With P2..P9 the 8 neighbours of a set pixel P1 clockwise from the one
 * above (pixels outside the image count as unset), B = how many are set
 * and A = how many 0 -> 1 transitions the cyclic sequence P2, ..., P9, P2
 * has, each iteration runs two sub-passes; sub-pass 1 removes, all at
 * once, every set pixel with 2 <= B <= 6, A = 1, P2 P4 P6 = 0 and
 * P4 P6 P8 = 0; sub-pass 2 the same with P2 P4 P8 = 0 and P2 P6 P8 = 0.
 * Iterations repeat until one removes nothing. A line already one pixel
 * wide keeps every pixel but its ends' corners; a blob shrinks to its
 * medial line. Deterministic and serial. */
#ifndef WS_SKELETON_H
#define WS_SKELETON_H
#include <stdint.h>
#include "nn/base/status.h"

/* set: H x W, nonzero = in the set; thinned in place (to 0/1). Fails only
 * when out of memory. */
int ws_skeleton_thin(uint8_t *set, int W, int H, ws_status *st);

#endif
