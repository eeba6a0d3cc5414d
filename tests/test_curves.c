/* test_curves.c: Bezier evaluation, sampling into Gaussians, the backward
 * pass, curve files (round trip and every error) and the initialisation. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "render/curves.h"

static const char *tmpdir;

static double dist3(const double *a, const double *b) {
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static void set_curve(ws_curves *c, int ci, const double pts[WS_CURVE_FLOATS]) {
    memcpy(c->P + (size_t)ci * WS_CURVE_FLOATS, pts, WS_CURVE_FLOATS * sizeof(double));
}

static void test_bernstein(void) {
    double B[4];
    for (int k = 0; k <= 10; k++) {
        ws_bernstein(k / 10.0, B);
        CHECK(fabs(B[0] + B[1] + B[2] + B[3] - 1) < 1e-15, "Bernstein weights sum to 1 at t %g", k / 10.0);
    }
    ws_curves c;
    ws_status st;
    CHECK(ws_curves_alloc(&c, 1, &st) == WS_OK, "alloc");
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    double p[3];
    ws_curve_point(&c, 0, 0, p);
    CHECK(p[0] == 1 && p[1] == 2 && p[2] == 3, "curve starts at P0");
    ws_curve_point(&c, 0, 1, p);
    CHECK(p[0] == 10 && p[1] == 11 && p[2] == 12, "curve ends at P3");
    ws_curve_point(&c, 0, 0.5, p);
    CHECK(fabs(p[0] - 5.5) < 1e-14, "midpoint of an evenly spaced line is its middle: %g", p[0]);
    ws_curves_free(&c);
}

/* Straight line with even control points: t is proportional to arc length. */
static void test_sampling_counts(void) {
    ws_curves c;
    ws_gaussians g = {0};
    ws_status st;
    ws_curves_alloc(&c, 1, &st);
    c.thickness = 0.02;
    c.overlap = 0.6; /* spacing 0.016 */
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){0, 0, 0, 0.1 / 3, 0, 0, 0.2 / 3, 0, 0, 0.1, 0, 0});
    CHECK(ws_curves_sample(&c, &g, &st) == WS_OK, "sample: %s", st.msg);
    CHECK(g.n == 7, "L 0.1 / spacing 0.016 = 6.25 -> 7 Gaussians, got %d", g.n);
    CHECK(g.t[0] == 0 && g.t[g.n - 1] == 1, "t_0 = 0 and t_{M-1} = 1");
    double worst = 0;
    for (int k = 1; k < g.n; k++) worst = fmax(worst, fabs(dist3(g.mu + 3 * k, g.mu + 3 * (k - 1)) - 0.1 / 6));
    CHECK(worst < 1e-12, "even spacing L / (M - 1), worst error %g", worst);

    /* Uneven parametrisation (points bunched at the start): arc-length
     * inversion still spaces the Gaussians evenly. */
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0});
    ws_curves_sample(&c, &g, &st);
    CHECK(g.n == 63, "L 1 -> ceil(62.5) = 63 Gaussians, got %d", g.n);
    double lo = 1e9, hi = 0;
    for (int k = 1; k < g.n; k++) {
        double s = dist3(g.mu + 3 * k, g.mu + 3 * (k - 1));
        lo = fmin(lo, s);
        hi = fmax(hi, s);
    }
    CHECK(hi / lo < 1.01, "spacing even within 1%%: min %g max %g", lo, hi);
    for (int k = 1; k < g.n; k++) CHECK(g.t[k] > g.t[k - 1], "t increasing at %d", k);

    /* A curved curve: consecutive chords are nearly equal. */
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){0, 0, 0, 0.3, 0.5, 0, 0.8, -0.4, 0.2, 1, 0.1, 0.3});
    ws_curves_sample(&c, &g, &st);
    lo = 1e9, hi = 0;
    for (int k = 1; k < g.n; k++) {
        double s = dist3(g.mu + 3 * k, g.mu + 3 * (k - 1));
        lo = fmin(lo, s);
        hi = fmax(hi, s);
    }
    CHECK(hi / lo < 1.01, "curved: spacing even within 1%%: %g %g", lo, hi);

    /* Short curve (L < s): one Gaussian at the arc-length midpoint. */
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){0, 0, 0, 0, 0, 0, 0, 0, 0, 0.01, 0, 0});
    ws_curves_sample(&c, &g, &st);
    CHECK(g.n == 1, "L 0.01 < s: one Gaussian, got %d", g.n);
    CHECK(fabs(g.mu[0] - 0.005) < 1e-6, "at the arc-length midpoint x 0.005, got %g", g.mu[0]);

    /* Degenerate: all points equal. */
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3});
    ws_curves_sample(&c, &g, &st);
    CHECK(g.n == 1 && g.t[0] == 0.5, "degenerate: one Gaussian at t 0.5 (n %d)", g.n);
    CHECK(fabs(g.mu[0] - 1) < 1e-15 && fabs(g.mu[1] - 2) < 1e-15 && fabs(g.mu[2] - 3) < 1e-15,
          "degenerate: at the point, no NaN");

    /* Overlap 0: spacing 2 * thickness. */
    c.overlap = 0;
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){0, 0, 0, 0.1 / 3, 0, 0, 0.2 / 3, 0, 0, 0.1, 0, 0});
    ws_curves_sample(&c, &g, &st);
    CHECK(g.n == 3, "overlap 0: L 0.1 / 0.04 -> 3, got %d", g.n);
    ws_gaussians_free(&g);
    ws_curves_free(&c);
}

static void test_cap_and_order(void) {
    ws_curves c;
    ws_gaussians g = {0};
    ws_status st;
    ws_curves_alloc(&c, 3, &st);
    set_curve(&c, 0, (double[WS_CURVE_FLOATS]){0, 0, 0, 0, 0, 0, 0, 0, 0, 0.1, 0, 0});
    set_curve(&c, 1, (double[WS_CURVE_FLOATS]){0, 0, 0, 300, 0, 0, 700, 0, 0, 1000, 0, 0}); /* L 1000 */
    set_curve(&c, 2, (double[WS_CURVE_FLOATS]){5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5});
    CHECK(ws_curves_sample(&c, &g, &st) == WS_OK, "long curve samples: %s", st.msg);
    int count[3] = {0, 0, 0}, ordered = 1;
    for (int k = 0; k < g.n; k++) {
        count[g.curve[k]]++;
        if (k && g.curve[k] < g.curve[k - 1]) ordered = 0;
        if (k && g.curve[k] == g.curve[k - 1] && !(g.t[k] > g.t[k - 1])) ordered = 0;
    }
    CHECK(ordered, "Gaussians in curve order, t increasing within a curve");
    CHECK(count[1] == WS_MAX_GAUSSIANS_PER_CURVE, "capped at %d, got %d", WS_MAX_GAUSSIANS_PER_CURVE,
          count[1]);
    CHECK(count[0] == 7 && count[2] == 1, "other curves unchanged: %d %d", count[0], count[2]);
    CHECK(g.capped == 1, "one capped curve counted, got %d", g.capped);
    double last = g.mu[3 * (7 + WS_MAX_GAUSSIANS_PER_CURVE - 1)];
    CHECK(last == 1000, "capped curve still spans its length: last x %g", last);

    c.P[0] = NAN;
    CHECK(ws_curves_sample(&c, &g, &st) == WS_ENUMERIC &&
              !strcmp(st.msg, "curves: curve 0 has a non-finite control point"),
          "NaN control point refused: %s", st.msg);
    c.P[0] = 0;
    c.thickness = 0;
    CHECK(ws_curves_sample(&c, &g, &st) == WS_EINPUT && strstr(st.msg, "thickness 0"),
          "thickness 0 refused: %s", st.msg);
    c.thickness = 0.02;
    c.overlap = 1;
    CHECK(ws_curves_sample(&c, &g, &st) == WS_EINPUT && strstr(st.msg, "overlap 1"),
          "overlap 1 refused: %s", st.msg);
    ws_gaussians_free(&g);
    ws_curves_free(&c);
}

/* dP = sum_k B(t_k) dmu_k against central differences of
 * L(P) = sum_k a_k . mu_k(P) with the t_k held fixed (as METHOD.md section 2 asks). */
static void test_backward(void) {
    ws_curves c;
    ws_gaussians g = {0};
    ws_status st;
    ws_rng rng;
    ws_rng_seed(&rng, 5);
    ws_curves_alloc(&c, 4, &st);
    for (int k = 0; k < 48; k++) c.P[k] = ws_rng_normal(&rng) * 0.1;
    ws_curves_sample(&c, &g, &st);
    double *a = malloc(sizeof(double) * g.n * 3), dP[48];
    for (int k = 0; k < g.n * 3; k++) a[k] = ws_rng_normal(&rng);
    ws_curves_backward(&c, &g, a, dP);
    double worst = 0;
    for (int k = 0; k < 48; k++) {
        double saved = c.P[k], L[2], h = 1e-6;
        for (int s = 0; s < 2; s++) {
            c.P[k] = saved + (s ? -h : h);
            L[s] = 0;
            for (int q = 0; q < g.n; q++) {
                double p[3];
                ws_curve_point(&c, g.curve[q], g.t[q], p);
                L[s] += a[3 * q] * p[0] + a[3 * q + 1] * p[1] + a[3 * q + 2] * p[2];
            }
        }
        c.P[k] = saved;
        double fd = (L[0] - L[1]) / (2 * h);
        CHECK(check_close(dP[k], fd, 1e-7, 1e-3), "dP[%d] %g vs FD %g", k, dP[k], fd);
        worst = fmax(worst, fabs(dP[k] - fd));
    }
    printf("curves backward: worst |dP - FD| = %.2e over %d Gaussians\n", worst, g.n);
    free(a);
    ws_gaussians_free(&g);
    ws_curves_free(&c);
}

static const char *write_file(const char *name, const char *text) {
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    return path;
}

static void test_files(void) {
    ws_curves c, back;
    ws_status st;
    ws_rng rng;
    ws_rng_seed(&rng, 11);
    ws_curves_alloc(&c, 5, &st);
    for (int k = 0; k < 60; k++) c.P[k] = ws_rng_normal(&rng) * pow(10, (int)ws_rng_below(&rng, 40) - 20);
    c.P[0] = 1.0 / 3.0;
    c.P[1] = -0.0;
    c.P[2] = 5e-324;
    c.P[3] = 1.2345678901234567e150; /* larger and the curve's length overflows: refused on load */
    c.thickness = 0.1 / 3;
    c.overlap = 0.6;
    char path[512];
    snprintf(path, sizeof path, "%s/round.json", tmpdir);
    CHECK(ws_curves_save(path, &c, &st) == WS_OK, "save: %s", st.msg);
    CHECK(ws_curves_load(path, &back, &st) == WS_OK, "load: %s", st.msg);
    CHECK(back.n == 5 && back.thickness == c.thickness && back.overlap == c.overlap,
          "round trip: count, thickness, overlap");
    CHECK(back.n == 5 && !memcmp(back.P, c.P, 60 * sizeof(double)), "round trip is bit-exact");
    ws_curves_free(&back);

    c.P[7] = INFINITY;
    CHECK(ws_curves_save(path, &c, &st) == WS_ENUMERIC, "saving Inf refused");
    ws_curves_free(&c);

    ws_curves_alloc(&c, 0, &st);
    CHECK(ws_curves_save(path, &c, &st) == WS_OK && ws_curves_load(path, &back, &st) == WS_OK &&
              back.n == 0,
          "an empty sketch round-trips: %s", st.msg);
    ws_curves_free(&back);
    ws_curves_free(&c);

    static const struct {
        const char *text, *msg; /* msg follows "PATH: " */
    } bad[] = {
        {"", "JSON syntax error near line 1"},
        {"{\n\"thickness\": 0.02,\n\"overlap\": 0.5,\n\"curves\": [[[1,2,3] [4,5,6]]]\n}",
         "JSON syntax error near line 4"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": []}\n\nx", "JSON syntax error near line 3"},
        {"[1, 2]", "not a JSON object"},
        {"{\"overlap\": 0.5, \"curves\": []}", "missing \"thickness\""},
        {"{\"thickness\": \"thin\", \"overlap\": 0.5, \"curves\": []}", "\"thickness\" is not a finite number"},
        {"{\"thickness\": 0.02, \"curves\": []}", "missing \"overlap\""},
        {"{\"thickness\": 0, \"overlap\": 0.5, \"curves\": []}", "thickness 0 is not positive"},
        {"{\"thickness\": 1e999, \"overlap\": 0.5, \"curves\": []}", "\"thickness\" is not a finite number"},
        {"{\"thickness\": 0.02, \"overlap\": 1, \"curves\": []}", "overlap 1 is not in [0, 1)"},
        {"{\"thickness\": 0.02, \"overlap\": -0.1, \"curves\": []}", "overlap -0.1 is not in [0, 1)"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5}", "missing \"curves\""},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": {}}", "\"curves\" is not an array"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": [[[0,0,0],[0,0,0],[0,0,0],[0,0,0]], "
         "[[0,0,0],[0,0,0],[0,0,0]]]}",
         "curve 1 is not 4 points"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": [7]}", "curve 0 is not 4 points"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": [[[0,0,0],[0,0,0],[0,0],[0,0,0]]]}",
         "curve 0: point 2 is not 3 numbers"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": [[[0,0,0],[0,0,0],[0,0,0],[0,\"1\",0]]]}",
         "curve 0: point 3 is not 3 numbers"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": [[[0,0,0],[0,0,0],[0,0,0],[0,0,0,0]]]}",
         "curve 0: point 3 is not 3 numbers"},
        {"{\"thickness\": 0.02, \"overlap\": 0.5, \"curves\": [[[0,0,0],[0,1e999,0],[0,0,0],[0,0,0]]]}",
         "curve 0: point 1 is not finite"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *p = write_file("bad.json", bad[k].text);
        char want[1024];
        snprintf(want, sizeof want, "%s: %s", p, bad[k].msg);
        ws_status_clear(&st);
        int rc = ws_curves_load(p, &c, &st);
        CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "bad file %zu: got '%s', want '%s'", k,
              st.msg, want);
        CHECK(c.n == 0 && c.P == NULL, "bad file %zu leaves the curves empty", k);
    }
    snprintf(path, sizeof path, "%s/missing.json", tmpdir);
    CHECK(ws_curves_load(path, &c, &st) == WS_EINPUT && strstr(st.msg, "missing.json: cannot open"),
          "missing file: %s", st.msg);
}

static void test_init(void) {
    ws_curves c, again;
    ws_status st;
    ws_rng rng;
    const double center[3] = {12.5, -3, 0.25};
    const int n = 2000;
    ws_rng_seed(&rng, 99);
    CHECK(ws_curves_init_random(&c, n, center, 0.8, 0.02, 0.02, 0.6, &rng, &st) == WS_OK,
          "init: %s", st.msg);
    CHECK(c.n == n && c.thickness == 0.02 && c.overlap == 0.6, "init sets count and shape");
    double worst_r = 0, worst_len = 0, worst_dot = 0, worst_col = 0, mean[3] = {0, 0, 0};
    for (int ci = 0; ci < n; ci++) {
        const double *P = c.P + (size_t)ci * WS_CURVE_FLOATS;
        double mid[3], dir[3], radial[3];
        for (int x = 0; x < 3; x++) {
            mid[x] = 0.5 * (P[3 + x] + P[6 + x]);
            dir[x] = P[9 + x] - P[x];
            radial[x] = mid[x] - center[x];
        }
        double r = sqrt(radial[0] * radial[0] + radial[1] * radial[1] + radial[2] * radial[2]);
        double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        worst_r = fmax(worst_r, fabs(r - 0.8));
        worst_len = fmax(worst_len, fabs(len - 0.02));
        worst_dot = fmax(worst_dot, fabs(radial[0] * dir[0] + radial[1] * dir[1] + radial[2] * dir[2]) / (r * len));
        for (int x = 0; x < 3; x++) {
            /* P1 = P0 + dir / 3, P2 = P0 + 2 dir / 3 */
            worst_col = fmax(worst_col, fabs(P[3 + x] - (P[x] + dir[x] / 3)));
            worst_col = fmax(worst_col, fabs(P[6 + x] - (P[x] + 2 * dir[x] / 3)));
            mean[x] += radial[x] / r / n;
        }
    }
    CHECK(worst_r < 1e-12, "midpoints on the sphere: worst |r - 0.8| %g", worst_r);
    CHECK(worst_len < 1e-12, "segment length 0.02: worst error %g", worst_len);
    double worst_measured = 0;
    for (int ci = 0; ci < n; ci++) worst_measured = fmax(worst_measured, fabs(ws_curve_length(&c, ci) - 0.02));
    CHECK(worst_measured < 1e-12, "ws_curve_length of the segments 0.02: worst error %g", worst_measured);
    CHECK(worst_dot < 1e-9, "direction tangent to the sphere: worst |cos| %g", worst_dot);
    CHECK(worst_col < 1e-12, "control points at -1/2, -1/6, 1/6, 1/2: worst %g", worst_col);
    double m = sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
    CHECK(m < 0.06, "points spread over the sphere: |mean direction| %g", m);
    ws_rng_seed(&rng, 99);
    ws_curves_init_random(&again, n, center, 0.8, 0.02, 0.02, 0.6, &rng, &st);
    CHECK(!memcmp(again.P, c.P, sizeof(double) * n * WS_CURVE_FLOATS), "same seed, same curves");
    ws_curves_free(&again);
    ws_curves_free(&c);
    CHECK(ws_curves_init_random(&c, 3, center, 0.8, 0.02, -1, 0.6, &rng, &st) == WS_EINPUT &&
              c.P == NULL,
          "negative thickness refused: %s", st.msg);
}

/* ws_curve_length of a bent curve against Simpson's rule on |B'(t)|. */
static void test_length(void) {
    ws_status st = {0};
    ws_curves c;
    ws_curves_alloc(&c, 2, &st);
    static const double P[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 1, 1, 1};
    memcpy(c.P, P, sizeof P);
    double simpson = 0;
    const int steps = 20000; /* even */
    for (int i = 0; i <= steps; i++) {
        double t = (double)i / steps, d[3];
        for (int x = 0; x < 3; x++) /* B'(t) = 3 [(1-t)^2 (P1-P0) + 2 t (1-t) (P2-P1) + t^2 (P3-P2)] */
            d[x] = 3 * ((1 - t) * (1 - t) * (P[3 + x] - P[x]) + 2 * t * (1 - t) * (P[6 + x] - P[3 + x]) +
                        t * t * (P[9 + x] - P[6 + x]));
        double w = i == 0 || i == steps ? 1 : i % 2 ? 4 : 2;
        simpson += w * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / (3.0 * steps);
    }
    double measured = ws_curve_length(&c, 0);
    CHECK(fabs(measured - simpson) < 1e-4 * simpson, "bent curve: length %.9g, Simpson %.9g", measured, simpson);
    CHECK(ws_curve_length(&c, 1) == 0, "a curve of 4 equal points: length %g", ws_curve_length(&c, 1));
    ws_curves_free(&c);
}

int main(void) {
    tmpdir = test_tmpdir("curves");
    test_bernstein();
    test_sampling_counts();
    test_cap_and_order();
    test_backward();
    test_files();
    test_init();
    test_length();
    return check_summary();
}
