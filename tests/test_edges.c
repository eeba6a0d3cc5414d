/* test_edges.c: the edge map and the multi-scale blurred edge loss against a
 * naive implementation of their definition (edges.h), and its gradient. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "check.h"
#include "reference_pyramid.h"
#include "render/edges.h"
#include "nn/base/rng.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The definition of edges.h written out the slow way: explicit pyramid and
 * a 2-D Gaussian kernel. */
static double reference_loss(const double *alpha, const float *edge, int W, int H) {
    double *d = malloc((size_t)W * H * sizeof *d), *next = malloc((size_t)W * H * sizeof *next);
    for (int p = 0; p < W * H; p++) d[p] = alpha[p] - edge[p];
    int w = W, h = H;
    double loss = 0;
    for (int s = 0; s < WS_EDGES_LEVELS; s++) {
        if (s > 0) {
            ref_pool(d, w, h, next);
            w = (w + 1) / 2, h = (h + 1) / 2;
            memcpy(d, next, (size_t)w * h * sizeof *d);
        }
        ref_blur(d, w, h, WS_EDGES_SIGMA, next);
        double level = 0;
        for (int p = 0; p < w * h; p++) level += next[p] * next[p];
        loss += level / (w * h) / WS_EDGES_LEVELS;
    }
    free(d);
    free(next);
    return loss;
}

static void test_edge_map(void) {
    enum { W = 30, H = 12 };
    static float photo[3 * W * H], edge[W * H];
    /* Three vertical bands: red, blue, green, so Y = 0.299, 0.114, 0.587. */
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            int band = j / 10; /* 0 red, 1 blue, 2 green */
            photo[0 * W * H + i * W + j] = band == 0;
            photo[2 * W * H + i * W + j] = band == 1;
            photo[1 * W * H + i * W + j] = band == 2;
        }
    ws_edges_target(photo, W, H, edge);
    /* Both edges are clear edges (above a tenth of the strongest) and equally
     * long, so the scale is their mean: the weaker one becomes 2r / (1 + r)
     * of it, the stronger one is clamped to 1. */
    double r = (0.299 - 0.114) / (0.587 - 0.114), ratio = 2 * r / (1 + r), worst = 0;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            double want = (j == 9 || j == 10) ? ratio : (j == 19 || j == 20) ? 1 : 0;
            worst = fmax(worst, fabs(edge[i * W + j] - want));
        }
    CHECK(worst < 1e-6, "edge map of three colour bands: off by %g", worst);
    for (int p = 0; p < 3 * W * H; p++) photo[p] = 0.25f + 0.5f * (p >= W * H);
    ws_edges_target(photo, W, H, edge);
    double sum = 0;
    for (int p = 0; p < W * H; p++) sum += fabs(edge[p]);
    CHECK(sum == 0, "edge map of a blank photo: sum %g, not 0", sum);
    ws_edges_workspace *ws = NULL;
    ws_status st = {0};
    CHECK(ws_edges_workspace_create(&ws, W, H, &st) == WS_OK, "%s", st.msg);
    static double alpha[W * H], dalpha[W * H];
    for (int p = 0; p < W * H; p++) alpha[p] = (p % 7) / 7.0;
    double loss = ws_edges_loss_forward(alpha, edge, W, H, ws);
    ws_edges_loss_backward(alpha, edge, W, H, ws, dalpha);
    int finite = 1;
    for (int p = 0; p < W * H; p++) finite &= isfinite(dalpha[p]);
    CHECK(isfinite(loss) && loss > 0 && finite, "blank photo: loss %g, gradient finite %d", loss, finite);
    CHECK(isnan(ws_edges_loss_forward(alpha, edge, W - 1, H, ws)), "a size mismatch gives NaN");
    ws_edges_workspace_free(ws);
}

/* Loss against the naive definition, and central differences of it, on an
 * odd size (partial pooling cells) and on a size that pools evenly. */
static void test_loss_and_gradient(int W, int H, uint64_t seed) {
    ws_rng rng;
    ws_rng_seed(&rng, seed);
    ws_status st = {0};
    size_t n = (size_t)W * H;
    double *alpha = malloc(n * sizeof *alpha), *dalpha = malloc(n * sizeof *dalpha);
    float *photo = malloc(3 * n * sizeof *photo), *edge = malloc(n * sizeof *edge);
    for (size_t p = 0; p < n; p++) alpha[p] = ws_rng_uniform(&rng);
    for (size_t p = 0; p < 3 * n; p++) photo[p] = (float)ws_rng_uniform(&rng);
    ws_edges_target(photo, W, H, edge);
    float emax = 0;
    for (size_t p = 0; p < n; p++) emax = fmaxf(emax, edge[p]);
    CHECK(emax == 1, "%dx%d: edge map maximum %g, not 1", W, H, emax);
    ws_edges_workspace *ws = NULL;
    CHECK(ws_edges_workspace_create(&ws, W, H, &st) == WS_OK, "%s", st.msg);
    double loss = ws_edges_loss_forward(alpha, edge, W, H, ws);
    double ref = reference_loss(alpha, edge, W, H);
    CHECK(check_close(loss, ref, 1e-12, 0), "%dx%d: loss %.15g, naive definition %.15g", W, H, loss, ref);
    ws_edges_loss_backward(alpha, edge, W, H, ws, dalpha);
    double worst = 0;
    for (int t = 0; t < 20; t++) {
        size_t p = t < 4 ? (size_t[]){0, W - 1, n - W, n - 1}[t] : ws_rng_below(&rng, n);
        const double h = 1e-3; /* the loss is quadratic: differences are exact but for rounding */
        double a0 = alpha[p];
        alpha[p] = a0 + h;
        double lp = ws_edges_loss_forward(alpha, edge, W, H, ws);
        alpha[p] = a0 - h;
        double lm = ws_edges_loss_forward(alpha, edge, W, H, ws);
        alpha[p] = a0;
        double fd = (lp - lm) / (2 * h);
        CHECK(check_close(fd, dalpha[p], 1e-6, 1e-9), "%dx%d pixel %zu: fd %.10g, backward %.10g", W,
              H, p, fd, dalpha[p]);
        worst = fmax(worst, fabs(fd - dalpha[p]) / fmax(fabs(fd), 1e-9));
    }
    printf("edge loss %dx%d: loss %.6g, naive %.6g, worst fd relative error %.1e\n", W, H, loss, ref, worst);
    ws_edges_workspace_free(ws);
    free(alpha);
    free(dalpha);
    free(photo);
    free(edge);
}

/* A stroke a few pixels beside an edge: the loss grows with the offset, and
 * the gradient pulls the stroke towards the edge (the basin of the blur). */
static void test_basin(void) {
    enum { W = 64, H = 48, EDGE = 30 };
    static float edge[W * H];
    static double alpha[W * H], dalpha[W * H];
    for (int i = 0; i < H; i++) edge[i * W + EDGE] = 1;
    ws_edges_workspace *ws = NULL;
    ws_status st = {0};
    CHECK(ws_edges_workspace_create(&ws, W, H, &st) == WS_OK, "%s", st.msg);
    double prev = -1;
    for (int off = 0; off <= 6; off++) {
        memset(alpha, 0, sizeof alpha);
        for (int i = 0; i < H; i++) alpha[i * W + EDGE + off] = 1;
        double loss = ws_edges_loss_forward(alpha, edge, W, H, ws);
        CHECK(loss > prev, "offset %d: loss %g does not exceed offset %d's %g", off, loss, off - 1, prev);
        prev = loss;
        if (off == 0) continue;
        ws_edges_loss_backward(alpha, edge, W, H, ws, dalpha);
        int i = H / 2, col = EDGE + off;
        CHECK(dalpha[i * W + col - 1] < dalpha[i * W + col + 1],
              "offset %d: gradient does not pull towards the edge (%g vs %g)", off,
              dalpha[i * W + col - 1], dalpha[i * W + col + 1]);
    }
    ws_edges_workspace_free(ws);
}

static void test_determinism_and_timing(void) {
    enum { W = 224, H = 224 };
    ws_rng rng;
    ws_rng_seed(&rng, 9);
    ws_status st = {0};
    static double alpha[W * H], d1[W * H], d2[W * H];
    static float photo[3 * W * H], edge[W * H];
    for (int p = 0; p < W * H; p++) alpha[p] = ws_rng_uniform(&rng);
    for (int p = 0; p < 3 * W * H; p++) photo[p] = (float)ws_rng_uniform(&rng);
    ws_edges_workspace *ws = NULL;
    CHECK(ws_edges_workspace_create(&ws, W, H, &st) == WS_OK, "%s", st.msg);
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    ws_edges_target(photo, W, H, edge);
    double l1 = ws_edges_loss_forward(alpha, edge, W, H, ws);
    ws_edges_loss_backward(alpha, edge, W, H, ws, d1);
    omp_set_num_threads(2);
    double l2 = ws_edges_loss_forward(alpha, edge, W, H, ws);
    ws_edges_loss_backward(alpha, edge, W, H, ws, d2);
    omp_set_num_threads(threads);
    CHECK(l1 == l2 && memcmp(d1, d2, sizeof d1) == 0, "1 and 2 threads differ: %.17g vs %.17g", l1, l2);
    /* The fastest of a few runs: the machine may be busy with other work. */
    double t_map = INFINITY, t_fwd = INFINITY, t_bwd = INFINITY;
    for (int r = 0; r < 10; r++) {
        double t0 = now();
        ws_edges_target(photo, W, H, edge);
        double t1 = now();
        l1 = ws_edges_loss_forward(alpha, edge, W, H, ws);
        double t2 = now();
        ws_edges_loss_backward(alpha, edge, W, H, ws, d1);
        double t3 = now();
        t_map = fmin(t_map, t1 - t0);
        t_fwd = fmin(t_fwd, t2 - t1);
        t_bwd = fmin(t_bwd, t3 - t2);
    }
    printf("224x224 (%d threads): edge map %.3f ms, loss forward %.3f ms, backward %.3f ms "
           "(fastest of 10)\n", threads, 1e3 * t_map, 1e3 * t_fwd, 1e3 * t_bwd);
    ws_edges_workspace_free(ws);
}

int main(void) {
    test_edge_map();
    test_loss_and_gradient(13, 11, 1);
    test_loss_and_gradient(64, 48, 2);
    test_basin();
    test_determinism_and_timing();
    return check_summary();
}
