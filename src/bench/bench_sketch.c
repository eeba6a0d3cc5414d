/* bench_sketch.c: the random sketch the benchmarks draw (bench.h). */
#include "bench/bench.h"

int ws_bench_sketch(ws_curves *c, int n, const double center[3], double radius, double length,
                    uint64_t seed, ws_status *st) {
    ws_rng rng;
    ws_rng_seed(&rng, seed);
    /* straight segments at random points of the sphere, as the original
     * initialises (METHOD.md section 2), scattered inward and bent by moving the inner
     * control points, so that strokes cross at every angle */
    if (ws_curves_init_random(c, n, center, radius, length, 0.02, 0.6, &rng, st)) return st->code;
    for (int k = 0; k < n; k++) {
        double *P = c->P + (size_t)k * WS_CURVE_FLOATS, inward = ws_rng_uniform(&rng), shift[3];
        for (int x = 0; x < 3; x++) shift[x] = -inward * (0.5 * (P[x] + P[9 + x]) - center[x]);
        for (int j = 0; j < 4; j++)
            for (int x = 0; x < 3; x++) {
                P[j * 3 + x] += shift[x];
                if (j == 1 || j == 2) P[j * 3 + x] += 0.3 * length * ws_rng_normal(&rng);
            }
    }
    return WS_OK;
}

int ws_bench_scaled(const ws_curves *c, double scale, const double center[3], ws_curves *out,
                    ws_status *st) {
    if (ws_curves_alloc(out, c->n, st)) return st->code;
    out->thickness = c->thickness;
    out->overlap = c->overlap;
    for (int i = 0; i < c->n * WS_CURVE_FLOATS; i++)
        out->P[i] = center[i % 3] + scale * (c->P[i] - center[i % 3]);
    return WS_OK;
}
