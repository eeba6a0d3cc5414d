/* nearest.h: exact nearest-neighbour queries against a fixed point set.
 *
 * A k-d tree: built once over the set (median splits on the widest axis,
 * leaves of at most WS_NEAREST_LEAF points, every node holding the tight
 * bounding box of its points), then queried by many points in parallel.
 * Tight boxes matter for surface scans: a query far from a thin surface
 * would otherwise visit every cell whose half-space reaches it. Queries are
 * exact: the answer is the point a brute-force scan finds, with the same
 * floating-point distance sqrt(dx*dx + dy*dy + dz*dz), ties going to the
 * lowest index. Results do not depend on the thread count. */
#ifndef WS_NEAREST_H
#define WS_NEAREST_H
#include "io/pointcloud.h"
#include "nn/base/status.h"

#define WS_NEAREST_LEAF 32

typedef struct {
    int n;             /* points in the set */
    double *xyz;       /* n x 3, reordered so that each leaf is contiguous */
    int *index;        /* n: position of each reordered point in the input */
    int depth;         /* levels of inner nodes; 0: the root is a leaf */
    double *box;       /* 2^(depth+1) - 1 nodes in heap order (children of
                          node i: 2i+1, 2i+2) x 6: lo xyz, hi xyz of its points */
} ws_nearest;

/* Builds the tree over 1 <= n <= WS_MAX_POINTS finite points (copied). */
int ws_nearest_build(ws_nearest *t, const double *xyz, int n, ws_status *st);
void ws_nearest_free(ws_nearest *t);

/* For each of the nq <= WS_MAX_POINTS finite query points q (nq x 3): dist[i] = distance to
 * the nearest point of the set and, when index is not NULL, index[i] = that
 * point's position in the input of ws_nearest_build. */
void ws_nearest_query(const ws_nearest *t, const double *q, int nq, double *dist, int *index);

#endif
