/* convex_fill.c: a set of pixels made convex (see convex_fill.h). */
#include <stdlib.h>
#include "render/convex_fill.h"

typedef struct {
    long long y, x;
} corner;

/* Floor and ceiling of n / d for d > 0, rounding as mathematics does. */
static long long floor_div(long long n, long long d) { return n >= 0 ? n / d : -((-n + d - 1) / d); }
static long long ceil_div(long long n, long long d) { return -floor_div(-n, d); }

/* Appends p to the chain of *n corners (increasing y), first dropping the
 * corners it makes no longer a vertex: side -1 keeps the chain the
 * envelope on the left (the least x), +1 on the right. */
static void chain_push(corner *chain, int *n, corner p, int side) {
    while (*n >= 2) {
        const corner a = chain[*n - 2], b = chain[*n - 1];
        /* b against the line from a to p at b's level: > 0 right of it */
        const long long right = (b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y);
        if (side * right > 0) break;
        (*n)--;
    }
    chain[(*n)++] = p;
}

/* 2 x (the chain's x at level i + 1/2) x dy, and dy, of the chain's
 * segment over row i; *at: the segment, advanced as the rows go down. */
static long long chain_at(const corner *chain, int n, long long i, int *at, long long *dy) {
    while (*at + 2 < n && chain[*at + 1].y <= i) (*at)++;
    const corner a = chain[*at], c = chain[*at + 1];
    *dy = c.y - a.y;
    return 2 * a.x * *dy + (c.x - a.x) * (2 * i + 1 - 2 * a.y);
}

int ws_convex_fill(float *mask, int W, int H, ws_status *st) {
    if (W <= 0 || H <= 0) return WS_OK;
    int *lo = ws_malloc(sizeof *lo * 2 * (size_t)H, "convex fill", st), *hi = lo ? lo + H : NULL;
    corner *left = lo ? ws_malloc(sizeof *left * 2 * ((size_t)H + 1), "convex fill", st) : NULL;
    if (!left) {
        free(lo);
        return st->code;
    }
    corner *right = left + H + 1;
    int first = -1, last = -1, nl = 0, nr = 0;
    for (int i = 0; i < H; i++) {
        const float *row = mask + (size_t)i * W;
        lo[i] = -1;
        for (int j = 0; j < W; j++)
            if (row[j] > 0.5f) {
                if (lo[i] < 0) lo[i] = j;
                hi[i] = j + 1; /* the square's right side */
            }
        if (lo[i] < 0) continue;
        if (first < 0) first = i;
        last = i;
    }
    /* level y holds the lower corners of row y - 1 and the upper of row y */
    for (int y = first; first >= 0 && y <= last + 1; y++) {
        const int above = y - 1 >= 0 && lo[y - 1] >= 0, below = y < H && lo[y] >= 0;
        if (!above && !below) continue;
        const int l = above && below ? (lo[y - 1] < lo[y] ? lo[y - 1] : lo[y]) : above ? lo[y - 1] : lo[y];
        const int r = above && below ? (hi[y - 1] > hi[y] ? hi[y - 1] : hi[y]) : above ? hi[y - 1] : hi[y];
        chain_push(left, &nl, (corner){y, l}, -1);
        chain_push(right, &nr, (corner){y, r}, +1);
    }
    int at_left = 0, at_right = 0;
    for (int i = first; first >= 0 && i <= last; i++) {
        long long dl, dr;
        const long long xl = chain_at(left, nl, i, &at_left, &dl), xr = chain_at(right, nr, i, &at_right, &dr);
        /* centre j + 1/2 in: (2j + 1) dl >= xl and (2j + 1) dr <= xr */
        long long j0 = ceil_div(xl - dl, 2 * dl), j1 = floor_div(xr - dr, 2 * dr);
        if (j0 < 0) j0 = 0;
        if (j1 > W - 1) j1 = W - 1;
        float *row = mask + (size_t)i * W;
        for (long long j = j0; j <= j1; j++)
            if (!(row[j] > 0.5f)) row[j] = 1;
    }
    free(lo);
    free(left);
    return WS_OK;
}
