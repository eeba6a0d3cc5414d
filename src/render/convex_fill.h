/* convex_fill.h: a set of pixels made convex: every pixel whose centre
 * lies in the closed convex hull of the set's pixels (the unit squares
 * [j, j+1] x [i, i+1]) joins the set.
 *
 * The hull of the squares is the hull of their corners, and only each
 * row's outermost corners can be its vertices, so the hull is two chains
 * over the corner levels y = 0..H: the left one the lower convex envelope
 * of the leftmost corner x at each level, the right one the upper envelope
 * of the rightmost (Andrew's monotone chain, the levels already in order).
 * A row is then filled between the chains at y = i + 1/2. Corners are
 * integers and centres half-integers, so every test is exact integer
 * arithmetic: a centre on the hull's edge is in, on any machine.
 * O(W H) time, O(H) memory. The edges' consensus (objective/
 * edge_consensus.h) fills a solid's photo hull this way in each view. */
#ifndef WS_CONVEX_FILL_H
#define WS_CONVEX_FILL_H
#include "nn/base/status.h"

/* mask: H x W; the set is its pixels > 1/2, and the pixels added are set
 * to 1 (the others are left as they are). Fails only when out of memory. */
int ws_convex_fill(float *mask, int W, int H, ws_status *st);

#endif
