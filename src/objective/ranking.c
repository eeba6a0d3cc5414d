/* ranking.c: the variants an objective must rank below the ground truth
 * (see ranking.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "metrics/metrics.h"
#include "objective/ranking.h"

const char *const ws_rank_names[WS_RANK_COUNT] = {
    "ground truth", "empty sketch", "a single dot", "shrunk to dots",
    "half of the curves", "shifted by 1%", "shifted by 5%", "plus 10 random strokes"};

#define NOISE_STROKES 10

int ws_rank_curves(const ws_curves *gt) { return gt->n + NOISE_STROKES; }

/* Variant `kind` of gt at thickness `thickness` into out (allocated here;
 * n = 0 for WS_RANK_EMPTY). */
static int rank_variant(const ws_curves *gt, int kind, double thickness, uint64_t seed, ws_curves *out,
                        ws_status *st) {
    double lo[3], hi[3], c[3], S = 0;
    ws_curves_bbox(gt, lo, hi);
    for (int x = 0; x < 3; x++) {
        c[x] = 0.5 * (lo[x] + hi[x]);
        S = fmax(S, hi[x] - lo[x]);
    }
    int n = kind == WS_RANK_EMPTY ? 0 : kind == WS_RANK_DOT ? 1 : kind == WS_RANK_HALF ? (gt->n + 1) / 2
            : kind == WS_RANK_NOISE ? ws_rank_curves(gt) : gt->n;
    if (ws_curves_alloc(out, n ? n : 1, st)) return st->code;
    out->n = n;
    out->thickness = thickness;
    out->overlap = gt->overlap;
    const size_t F = WS_CURVE_FLOATS;
    const double u[3] = {1 / sqrt(14.0), 2 / sqrt(14.0), 3 / sqrt(14.0)};
    switch (kind) {
    case WS_RANK_DOT:
        for (int j = 0; j < 4; j++) memcpy(out->P + 3 * j, c, sizeof c);
        break;
    case WS_RANK_DOTS:
        for (int ci = 0; ci < gt->n; ci++) {
            double p[3];
            ws_curve_point(gt, ci, 0.5, p);
            for (int j = 0; j < 4; j++) memcpy(out->P + ci * F + 3 * j, p, sizeof p);
        }
        break;
    case WS_RANK_HALF:
        for (int ci = 0; ci < n; ci++) memcpy(out->P + ci * F, gt->P + 2 * ci * F, F * sizeof(double));
        break;
    case WS_RANK_SHIFT1:
    case WS_RANK_SHIFT5: {
        double d = (kind == WS_RANK_SHIFT1 ? 0.01 : 0.05) * S;
        for (size_t k = 0; k < (size_t)gt->n * 4; k++)
            for (int x = 0; x < 3; x++) out->P[3 * k + x] = gt->P[3 * k + x] + d * u[x];
        break;
    }
    case WS_RANK_NOISE: {
        memcpy(out->P, gt->P, (size_t)gt->n * F * sizeof(double));
        ws_rng rng;
        ws_rng_seed(&rng, seed);
        for (int k = 0; k < NOISE_STROKES; k++) {
            double m[3], dir[3], len = 0;
            for (int x = 0; x < 3; x++) m[x] = lo[x] + (hi[x] - lo[x]) * ws_rng_uniform(&rng);
            while (!(len > 1e-6)) {
                len = 0;
                for (int x = 0; x < 3; x++) {
                    dir[x] = ws_rng_normal(&rng);
                    len += dir[x] * dir[x];
                }
                len = sqrt(len);
            }
            double *P = out->P + (gt->n + k) * F;
            for (int j = 0; j < 4; j++)
                for (int x = 0; x < 3; x++) P[3 * j + x] = m[x] + 0.3 * S * (j / 3.0 - 0.5) * dir[x] / len;
        }
        break;
    }
    default: /* WS_RANK_TRUTH; nothing to copy for WS_RANK_EMPTY */
        memcpy(out->P, gt->P, (size_t)n * F * sizeof(double));
    }
    return WS_OK;
}

int ws_rank_score(ws_objective *obj, int split, const ws_curves *c, double *out, ws_status *st) {
    if (ws_objective_split_mean(obj, c, split, NULL, out, st)) return st->code;
    /* ws_objective_split_mean's mean of no views */
    if (isnan(*out)) return ws_fail(st, WS_EUSAGE, "rank: the %s split has no views", ws_split_names[split]);
    return WS_OK;
}

int ws_rank_losses(ws_objective *obj, int split, const ws_curves *gt, double thickness, uint64_t seed,
                   double loss_out[WS_RANK_COUNT], ws_status *st) {
    int rc = WS_OK;
    for (int kind = 0; kind < WS_RANK_COUNT && !rc; kind++) {
        ws_curves c = {0};
        rc = rank_variant(gt, kind, thickness, seed, &c, st);
        if (!rc) rc = ws_rank_score(obj, split, &c, &loss_out[kind], st);
        ws_curves_free(&c);
    }
    return rc;
}
