/* nearest.c: k-d tree for exact nearest-neighbour queries (see nearest.h).
 *
 * The tree is implicit: the node over points [lo, hi) splits at
 * mid = lo + (hi - lo) / 2, so only each node's bounding box is stored, and
 * every leaf sits at the same depth. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "metrics/nearest.h"

static void swap_points(ws_nearest *t, int i, int j) {
    for (int a = 0; a < 3; a++) {
        double v = t->xyz[i * 3 + a];
        t->xyz[i * 3 + a] = t->xyz[j * 3 + a];
        t->xyz[j * 3 + a] = v;
    }
    int k = t->index[i];
    t->index[i] = t->index[j];
    t->index[j] = k;
}

static double median3(double a, double b, double c) {
    return fmax(fmin(a, b), fmin(fmax(a, b), c));
}

/* Rearranges points [lo, hi) so that none before k has a larger coordinate
 * along axis a than point k and none after it a smaller one (Hoare's
 * selection; the median-of-three pivot keeps sorted input linear). */
static void select_kth(ws_nearest *t, int lo, int hi, int k, int a) {
    const double *x = t->xyz + a;
    int l = lo, r = hi - 1;
    while (l < r) {
        double pivot = median3(x[l * 3], x[(l + (r - l) / 2) * 3], x[r * 3]);
        int i = l, j = r;
        while (i <= j) {
            while (x[i * 3] < pivot) i++;
            while (x[j * 3] > pivot) j--;
            if (i <= j) swap_points(t, i++, j--);
        }
        /* Now [l, j] <= pivot <= [i, r] and everything strictly between
         * equals the pivot. */
        if (j < k) l = i;
        if (k < i) r = j;
    }
}

static void build_node(ws_nearest *t, int node, int lo, int hi, int level) {
    double *box = t->box + (size_t)node * 6;
    for (int a = 0; a < 3; a++) box[a] = box[3 + a] = t->xyz[lo * 3 + a];
    for (int i = lo + 1; i < hi; i++)
        for (int a = 0; a < 3; a++) {
            double v = t->xyz[i * 3 + a];
            if (v < box[a]) box[a] = v;
            if (v > box[3 + a]) box[3 + a] = v;
        }
    if (level == t->depth) return;
    /* Split the widest extent: boxes stay compact, so pruning works. */
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (box[3 + a] - box[a] > box[3 + axis] - box[axis]) axis = a;
    int mid = lo + (hi - lo) / 2;
    select_kth(t, lo, hi, mid, axis);
    /* The halves are disjoint and built by the same steps whichever thread
     * runs them, so the tree does not depend on the thread count. */
#pragma omp task if (hi - lo > 65536)
    build_node(t, 2 * node + 1, lo, mid, level + 1);
    build_node(t, 2 * node + 2, mid, hi, level + 1);
#pragma omp taskwait
}

int ws_nearest_build(ws_nearest *t, const double *xyz, int n, ws_status *st) {
    memset(t, 0, sizeof *t);
    if (n < 1) return ws_fail(st, WS_EINPUT, "nearest-neighbour set is empty");
    if (n > WS_MAX_POINTS)
        return ws_fail(st, WS_EINPUT, "nearest-neighbour set: %d points exceed the limit of %d", n, WS_MAX_POINTS);
    for (int i = 0; i < n * 3; i++)
        if (!isfinite(xyz[i]))
            return ws_fail(st, WS_ENUMERIC, "nearest-neighbour set: point %d is not finite", i / 3);
    /* Halving [lo, hi) leaves ceil(n / 2^level) points at most per node. */
    int depth = 0;
    for (long long size = n; size > WS_NEAREST_LEAF; size = (size + 1) / 2) depth++;
    size_t nodes = ((size_t)2 << depth) - 1;
    t->n = n;
    t->depth = depth;
    t->xyz = ws_malloc((size_t)n * 3 * sizeof(double), "k-d tree points", st);
    t->index = t->xyz ? ws_malloc((size_t)n * sizeof(int), "k-d tree indices", st) : NULL;
    t->box = t->index ? ws_malloc(nodes * 6 * sizeof(double), "k-d tree boxes", st) : NULL;
    if (!t->box) {
        ws_nearest_free(t);
        return st->code;
    }
    memcpy(t->xyz, xyz, (size_t)n * 3 * sizeof(double));
    for (int i = 0; i < n; i++) t->index[i] = i;
#pragma omp parallel
#pragma omp single
    build_node(t, 0, 0, n, 0);
    return WS_OK;
}

void ws_nearest_free(ws_nearest *t) {
    free(t->xyz);
    free(t->index);
    free(t->box);
    memset(t, 0, sizeof *t);
}

typedef struct {
    const ws_nearest *t;
    double q[3];
    double best;    /* squared distance of the best point so far */
    int best_index; /* its input index */
} query_state;

/* Squared distance from q to a node's box, computed with the very
 * operations of the point distance below (q minus a face instead of q minus
 * a point beyond that face). Rounding is monotone, so no point in the box
 * has a computed distance below this bound: pruning on bound > best is
 * exact, and bound == best is still visited for the lowest-index tie rule. */
static double box_distance2(const double q[3], const double *box) {
    double d[3];
    for (int a = 0; a < 3; a++)
        d[a] = q[a] < box[a] ? q[a] - box[a] : q[a] > box[3 + a] ? q[a] - box[3 + a] : 0;
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

static void search(query_state *s, int node, int lo, int hi, int level) {
    const ws_nearest *t = s->t;
    if (level == t->depth) {
        for (int i = lo; i < hi; i++) {
            const double *p = t->xyz + i * 3;
            double dx = s->q[0] - p[0], dy = s->q[1] - p[1], dz = s->q[2] - p[2];
            double d2 = dx * dx + dy * dy + dz * dz;
            if (d2 < s->best || (d2 == s->best && t->index[i] < s->best_index)) {
                s->best = d2;
                s->best_index = t->index[i];
            }
        }
        return;
    }
    /* The nearer child first: it most likely shrinks `best` enough to
     * prune the other. */
    int mid = lo + (hi - lo) / 2, left = 2 * node + 1;
    double dl = box_distance2(s->q, t->box + (size_t)left * 6);
    double dr = box_distance2(s->q, t->box + (size_t)(left + 1) * 6);
    int first = dl <= dr ? 0 : 1;
    for (int k = 0; k < 2; k++) {
        int right = first ^ k;
        if ((right ? dr : dl) > s->best) continue;
        if (right) search(s, left + 1, mid, hi, level + 1);
        else search(s, left, lo, mid, level + 1);
    }
}

void ws_nearest_query(const ws_nearest *t, const double *q, int nq, double *dist, int *index) {
#pragma omp parallel for schedule(dynamic, 256)
    for (int i = 0; i < nq; i++) {
        query_state s = {.t = t, .q = {q[i * 3], q[i * 3 + 1], q[i * 3 + 2]},
                         .best = INFINITY, .best_index = INT_MAX};
        search(&s, 0, 0, t->n, 0);
        dist[i] = sqrt(s.best);
        if (index) index[i] = s.best_index;
    }
}
