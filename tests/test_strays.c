/* test_strays.c: precision over Gaussian centres and stray curves
 * (metrics/strays.h) on hand-made sketches whose answers are known: a
 * floating dot costs precision and counts as a stray curve, a curve with
 * most of its Gaussians off the ground truth is stray, one with most on it
 * is not. */
#include <math.h>
#include <string.h>
#include "check.h"
#include "metrics/metrics.h"
#include "metrics/strays.h"

/* A straight curve from a to b. */
static void segment(ws_curves *c, int ci, const double a[3], const double b[3]) {
    double *P = c->P + 12 * ci;
    for (int j = 0; j < 4; j++)
        for (int x = 0; x < 3; x++) P[3 * j + x] = a[x] + (b[x] - a[x]) * j / 3.0;
}

int main(void) {
    ws_status st;
    ws_curves gt, sk;
    ws_curves_alloc(&gt, 1, &st);
    const double o[3] = {0, 0, 0}, e[3] = {1, 0, 0};
    segment(&gt, 0, o, e); /* the ground truth: the unit segment on x, D = 1 */
    ws_gaussians dense = {0};
    ws_nearest tree;
    ws_curves_sample_dense(&gt, 0.001, &dense, &st);
    ws_nearest_build(&tree, dense.mu, dense.n, &st);

    ws_curves_alloc(&sk, 4, &st);
    sk.thickness = 0.01;
    sk.overlap = 0.5; /* Gaussians 0.01 apart */
    segment(&sk, 0, o, e);                                   /* on the truth */
    const double dot[3] = {0.5, 0.3, 0};
    segment(&sk, 1, dot, dot);                               /* a floating dot */
    const double a[3] = {0.9, 0, 0}, b[3] = {0.9, 0.405, 0}; /* 1/8 on, 7/8 beyond 5% */
    segment(&sk, 2, a, b);
    const double c0[3] = {0.2, 0, 0}, c1[3] = {0.2, 0.085, 0}; /* 6 of 10 within 5% */
    segment(&sk, 3, c0, c1);
    ws_stray_metrics m;
    CHECK(ws_stray_metrics_compute(&sk, &tree, 1.0, &m, &st) == WS_OK, "strays: %s", st.msg);
    ws_gaussians g = {0};
    ws_curves_sample(&sk, &g, &st);
    int close = 0;
    /* no centre lies on the 1% boundary, so the dense samples agree with |y| */
    for (int k = 0; k < g.n; k++) close += fabs(g.mu[3 * k + 1]) <= 0.01;
    CHECK(m.n_gaussians == g.n && m.n_curves == 4, "counts %d %d", m.n_gaussians, m.n_curves);
    CHECK(fabs(m.precision - (double)close / g.n) < 1e-12,
          "precision %g, want %d of %d Gaussians within 1%%", m.precision, close, g.n);
    CHECK(m.stray_curves == 2, "stray curves %d, want 2 (the dot and the mostly-off one)", m.stray_curves);
    /* a dot costs precision over Gaussians though it adds no arc length */
    ws_curves one = sk;
    one.n = 1;
    ws_stray_metrics m1;
    ws_stray_metrics_compute(&one, &tree, 1.0, &m1, &st);
    CHECK(m1.precision == 1.0 && m1.stray_curves == 0, "the truth alone: precision %g, %d stray",
          m1.precision, m1.stray_curves);
    one.n = 2;
    ws_stray_metrics_compute(&one, &tree, 1.0, &m1, &st);
    CHECK(m1.precision < 1.0 && m1.stray_curves == 1, "truth + dot: precision %g, %d stray",
          m1.precision, m1.stray_curves);
    ws_gaussians_free(&g);
    ws_gaussians_free(&dense);
    ws_nearest_free(&tree);
    ws_curves_free(&gt);
    ws_curves_free(&sk);
    return check_summary();
}
