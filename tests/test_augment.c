/* test_augment.c: the augmentation against torchvision, its transpose, its
 * sampling ranges, and its determinism. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "render/augment.h"
#include "check.h"

#define FIXTURE "tests/fixtures/augment_torchvision.txt"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void fill_random(float *x, size_t n, ws_rng *rng) {
    for (size_t i = 0; i < n; i++) x[i] = (float)(2 * ws_rng_uniform(rng) - 1);
}

static double dot(const float *a, const float *b, size_t n) {
    double s = 0;
    for (size_t i = 0; i < n; i++) s += (double)a[i] * b[i];
    return s;
}

static double max_abs_diff(const float *a, const double *b, size_t n) {
    double m = 0;
    for (size_t k = 0; k < n; k++) m = fmax(m, fabs(a[k] - b[k]));
    return m;
}

/* The fixture made by tools/make_augment_fixture.py (torchvision 0.14): the
 * output as torchvision computes it (homography solved in float32, ~1e-5
 * off), and with the homography solved in float64 (as here). */
static void test_torchvision_fixture(void) {
    FILE *f = fopen(FIXTURE, "r");
    CHECK(f != NULL, "%s: cannot open", FIXTURE);
    if (!f) return;
    int W, H, C, corner[4][2], top, left, ch, cw;
    int ok = fscanf(f, "%*[^\n] size %d %d %d corners %d %d %d %d %d %d %d %d crop %d %d %d %d input",
                    &W, &H, &C, &corner[0][0], &corner[0][1], &corner[1][0], &corner[1][1],
                    &corner[2][0], &corner[2][1], &corner[3][0], &corner[3][1], &top, &left, &ch,
                    &cw) == 15;
    CHECK(ok, "%s: bad header", FIXTURE);
    if (!ok) {
        fclose(f);
        return;
    }
    size_t n = (size_t)C * H * W;
    float *in = malloc(n * sizeof *in), *out = malloc(n * sizeof *out);
    double *torch = malloc(n * sizeof *torch), *exact = malloc(n * sizeof *exact);
    for (size_t k = 0; k < n && ok; k++) {
        int v;
        ok = fscanf(f, "%d", &v) == 1;
        in[k] = (float)(v / 255.0);
    }
    ok = ok && fscanf(f, " output") == 0;
    for (size_t k = 0; k < n && ok; k++) ok = fscanf(f, "%lf", &torch[k]) == 1;
    ok = ok && fscanf(f, " output_exact_homography") == 0;
    for (size_t k = 0; k < n && ok; k++) ok = fscanf(f, "%lf", &exact[k]) == 1;
    fclose(f);
    CHECK(ok, "%s: truncated", FIXTURE);
    ws_status st = {0};
    ws_aug_params p;
    ws_aug_workspace *ws = NULL;
    CHECK(ws_aug_params_init(&p, W, H, (const int(*)[2])corner, top, left, ch, cw, &st) == WS_OK,
          "%s", st.msg);
    CHECK(ws_aug_workspace_create(&ws, W, H, C, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_forward(&p, in, C, H, W, out, ws, &st) == WS_OK, "%s", st.msg);
    double d_torch = max_abs_diff(out, torch, n), d_exact = max_abs_diff(out, exact, n);
    double maxval = 0;
    for (size_t k = 0; k < n; k++) maxval = fmax(maxval, exact[k]);
    printf("torchvision fixture %dx%dx%d: max |ours - torchvision| = %.2e, with a float64 "
           "homography %.2e\n", C, H, W, d_torch, d_exact);
    CHECK(ok && d_exact < 1e-6, "torchvision fixture (float64 homography): max diff %g", d_exact);
    CHECK(ok && d_torch < 3e-5, "torchvision fixture: max diff %g", d_torch);
    CHECK(maxval > 0.5, "fixture output is not blank (max %g)", maxval);
    ws_aug_workspace_free(ws);
    free(in);
    free(out);
    free(torch);
    free(exact);
}

/* Corners that do not move and the whole image as the crop: the identity. */
static void test_identity(void) {
    enum { W = 37, H = 29 };
    const int corner[4][2] = {{0, 0}, {W - 1, 0}, {W - 1, H - 1}, {0, H - 1}};
    ws_status st = {0};
    ws_aug_params p;
    ws_aug_workspace *ws = NULL;
    ws_rng rng;
    ws_rng_seed(&rng, 5);
    float in[2 * W * H], out[2 * W * H];
    fill_random(in, 2 * W * H, &rng);
    CHECK(ws_aug_params_init(&p, W, H, corner, 0, 0, H, W, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_workspace_create(&ws, W, H, 2, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_forward(&p, in, 2, H, W, out, ws, &st) == WS_OK, "%s", st.msg);
    double maxdiff = 0;
    for (int k = 0; k < 2 * W * H; k++) maxdiff = fmax(maxdiff, fabs(out[k] - in[k]));
    CHECK(maxdiff < 1e-6, "identity transform changes the image by %g", maxdiff);
    ws_aug_workspace_free(ws);
}

/* Outside the warped quadrilateral the output is 0; well inside it an
 * all-ones image stays 1. */
static void test_fill_zero(void) {
    enum { W = 64, H = 64 };
    const int corner[4][2] = {{16, 16}, {47, 16}, {47, 47}, {16, 47}};
    ws_status st = {0};
    ws_aug_params p;
    ws_aug_workspace *ws = NULL;
    static float in[W * H], out[W * H];
    for (int k = 0; k < W * H; k++) in[k] = 1;
    CHECK(ws_aug_params_init(&p, W, H, corner, 0, 0, 57, 57, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_workspace_create(&ws, W, H, 1, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_forward(&p, in, 1, H, W, out, ws, &st) == WS_OK, "%s", st.msg);
    double outside = 0, lo = 1, hi = 0;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            float v = out[i * W + j];
            lo = fmin(lo, v);
            hi = fmax(hi, v);
            /* crop pixel (i, j) * 57/64 < 14 is outside the quad [16, 47]. */
            if (i < 12 || j < 12) outside = fmax(outside, fabs(v));
        }
    CHECK(outside == 0, "outside the warped image: %g, not 0", outside);
    CHECK(fabs(out[40 * W + 40] - 1) < 1e-6, "inside: %g, not 1", out[40 * W + 40]);
    CHECK(lo >= 0 && hi <= 1 + 1e-6, "an all-ones image warps into [%g, %g]", lo, hi);
    ws_aug_workspace_free(ws);
}

/* <A x, y> = <x, A^T y>, and central differences of L(x) = <y, A x>. */
static void test_adjoint(int W, int H, int C, uint64_t seed) {
    ws_status st = {0};
    ws_rng rng;
    ws_rng_seed(&rng, seed);
    ws_aug_params p;
    ws_aug_workspace *ws = NULL;
    size_t n = (size_t)C * H * W;
    float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *ax = malloc(n * sizeof *ax),
          *aty = malloc(n * sizeof *aty);
    fill_random(x, n, &rng);
    fill_random(y, n, &rng);
    CHECK(ws_aug_sample(&p, &rng, W, H, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_workspace_create(&ws, W, H, C, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_forward(&p, x, C, H, W, ax, ws, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_backward(&p, y, C, H, W, aty, ws, &st) == WS_OK, "%s", st.msg);
    double lhs = dot(ax, y, n), rhs = dot(x, aty, n);
    printf("%dx%dx%d: <Ax,y> %.10g, <x,A^T y> %.10g, relative difference %.1e\n", C, H, W, lhs,
           rhs, fabs(lhs - rhs) / fabs(lhs));
    CHECK(check_close(lhs, rhs, 1e-6, 0), "%dx%dx%d: <Ax,y> = %.12g, <x,A^T y> = %.12g", C, H, W,
          lhs, rhs);
    /* Central differences at pixels the warp reads (A^T y != 0) and at one
     * it cannot read (a corner of the source may lie outside the quad). */
    int tested = 0;
    for (int trial = 0; trial < 200 && tested < 12; trial++) {
        size_t k = ws_rng_below(&rng, n);
        if (aty[k] == 0 && tested > 0) continue;
        const float h = 0.5f;
        float x0 = x[k];
        x[k] = x0 + h;
        ws_aug_forward(&p, x, C, H, W, ax, ws, &st);
        double lp = dot(ax, y, n);
        x[k] = x0 - h;
        ws_aug_forward(&p, x, C, H, W, ax, ws, &st);
        double lm = dot(ax, y, n);
        x[k] = x0;
        double fd = (lp - lm) / (2 * h);
        CHECK(check_close(fd, aty[k], 1e-4, 1e-3), "%dx%dx%d pixel %zu: fd %.8g, backward %.8g", C,
              H, W, k, fd, aty[k]);
        tested++;
    }
    ws_aug_workspace_free(ws);
    free(x);
    free(y);
    free(ax);
    free(aty);
}

/* The ranges torchvision draws from, all of them reached; the fallback crop
 * of a wide image. */
static void test_sample_ranges(void) {
    enum { W = 224, H = 224 };
    ws_status st = {0};
    ws_rng rng;
    ws_rng_seed(&rng, 11);
    int lo[4][2], hi[4][2], top_lo = H, top_hi = 0, left_lo = W, left_hi = 0, side_ok = 1;
    for (int k = 0; k < 4; k++) lo[k][0] = lo[k][1] = 1 << 30, hi[k][0] = hi[k][1] = -1;
    for (int t = 0; t < 20000; t++) {
        ws_aug_params p;
        if (ws_aug_sample(&p, &rng, W, H, &st)) break;
        for (int k = 0; k < 4; k++)
            for (int a = 0; a < 2; a++) {
                if (p.corner[k][a] < lo[k][a]) lo[k][a] = p.corner[k][a];
                if (p.corner[k][a] > hi[k][a]) hi[k][a] = p.corner[k][a];
            }
        side_ok &= p.crop_height == 200 && p.crop_width == 200;
        if (p.crop_top < top_lo) top_lo = p.crop_top;
        if (p.crop_top > top_hi) top_hi = p.crop_top;
        if (p.crop_left < left_lo) left_lo = p.crop_left;
        if (p.crop_left > left_hi) left_hi = p.crop_left;
    }
    CHECK(st.code == WS_OK, "%s", st.msg);
    /* 224: distortion 0.5 * 112 = 56 pixels inward at most. */
    const int want_lo[4][2] = {{0, 0}, {167, 0}, {167, 167}, {0, 167}};
    const int want_hi[4][2] = {{56, 56}, {223, 56}, {223, 223}, {56, 223}};
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 2; a++)
            CHECK(lo[k][a] == want_lo[k][a] && hi[k][a] == want_hi[k][a],
                  "corner %d coordinate %d drawn in [%d, %d], want [%d, %d]", k, a, lo[k][a],
                  hi[k][a], want_lo[k][a], want_hi[k][a]);
    CHECK(side_ok, "crop side is not round(sqrt(0.8 * 224 * 224)) = 200");
    CHECK(top_lo == 0 && top_hi == 24 && left_lo == 0 && left_hi == 24,
          "crop top in [%d, %d], left in [%d, %d], want [0, 24]", top_lo, top_hi, left_lo, left_hi);
    ws_aug_params p;
    CHECK(ws_aug_sample(&p, &rng, 300, 100, &st) == WS_OK, "%s", st.msg);
    CHECK(p.crop_top == 0 && p.crop_left == 100 && p.crop_height == 100 && p.crop_width == 100,
          "300x100 fallback crop: top %d left %d %dx%d, want the centred 100x100", p.crop_top,
          p.crop_left, p.crop_width, p.crop_height);
}

/* The stroke image and a photo whose channels equal it stay equal: one
 * transform for both. Same seed, same bits, for 1 and 2 threads. */
static void test_same_transform_and_determinism(void) {
    enum { W = 96, H = 80 };
    ws_status st = {0};
    ws_rng rng1, rng2;
    ws_rng_seed(&rng1, 77);
    ws_rng_seed(&rng2, 77);
    ws_aug_params p1, p2;
    CHECK(ws_aug_sample(&p1, &rng1, W, H, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_sample(&p2, &rng2, W, H, &st) == WS_OK, "%s", st.msg);
    CHECK(memcmp(&p1, &p2, sizeof p1) == 0, "same seed, different transforms");
    ws_aug_workspace *ws = NULL;
    CHECK(ws_aug_workspace_create(&ws, W, H, 3, &st) == WS_OK, "%s", st.msg);
    static float stroke[W * H], photo[3 * W * H], s_out[W * H], p_out[3 * W * H],
        f1[3 * W * H], f2[3 * W * H], b1[3 * W * H], b2[3 * W * H];
    fill_random(stroke, W * H, &rng1);
    for (int c = 0; c < 3; c++) memcpy(photo + c * W * H, stroke, sizeof stroke);
    ws_aug_forward(&p1, stroke, 1, H, W, s_out, ws, &st);
    ws_aug_forward(&p1, photo, 3, H, W, p_out, ws, &st);
    int same = 1;
    for (int c = 0; c < 3; c++) same &= memcmp(p_out + c * W * H, s_out, sizeof s_out) == 0;
    CHECK(same, "a photo equal to the stroke image differs from it after augmentation");
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    ws_aug_forward(&p1, photo, 3, H, W, f1, ws, &st);
    ws_aug_backward(&p1, photo, 3, H, W, b1, ws, &st);
    omp_set_num_threads(2);
    ws_aug_forward(&p1, photo, 3, H, W, f2, ws, &st);
    ws_aug_backward(&p1, photo, 3, H, W, b2, ws, &st);
    omp_set_num_threads(threads);
    CHECK(st.code == WS_OK, "%s", st.msg);
    CHECK(memcmp(f1, f2, sizeof f1) == 0, "forward differs between 1 and 2 threads");
    CHECK(memcmp(b1, b2, sizeof b1) == 0, "backward differs between 1 and 2 threads");
    ws_aug_workspace_free(ws);
}

static void test_errors(void) {
    ws_status st = {0};
    ws_aug_params p;
    ws_rng rng;
    ws_rng_seed(&rng, 1);
    const int corner[4][2] = {{0, 0}, {9, 0}, {9, 9}, {0, 9}};
    CHECK(ws_aug_params_init(&p, 10, 10, corner, 2, 3, 9, 5, &st) == WS_EINPUT &&
              strcmp(st.msg, "augment: crop box (top 2, left 3, 5x9) is not inside the 10x10 image") == 0,
          "crop outside: %s", st.msg);
    const int flat[4][2] = {{0, 0}, {9, 0}, {5, 0}, {2, 0}};
    CHECK(ws_aug_params_init(&p, 10, 10, flat, 0, 0, 8, 8, &st) == WS_EINPUT &&
              strcmp(st.msg, "augment: corners (0,0) (9,0) (5,0) (2,0) are degenerate") == 0,
          "degenerate: %s", st.msg);
    CHECK(ws_aug_sample(&p, &rng, 1, 5, &st) == WS_EINPUT &&
              strcmp(st.msg, "augment: image size 1x5 is too small (needs 2x2)") == 0,
          "tiny: %s", st.msg);
    ws_aug_workspace *ws = NULL;
    float img[3 * 10 * 10] = {0}, out[3 * 10 * 10];
    CHECK(ws_aug_params_init(&p, 10, 10, corner, 0, 0, 8, 8, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_workspace_create(&ws, 10, 10, 1, &st) == WS_OK, "%s", st.msg);
    CHECK(ws_aug_forward(&p, img, 3, 10, 10, out, ws, &st) == WS_EINTERNAL &&
              strcmp(st.msg, "augment: 3-channel 10x10 image does not fit the 10x10 "
                             "transform or the 1-channel 10x10 workspace") == 0,
          "3 channels in a 1-channel workspace: %s", st.msg);
    ws_aug_workspace_free(ws);
}

static void time_224(int C) {
    enum { W = 224, H = 224 };
    ws_status st = {0};
    ws_rng rng;
    ws_rng_seed(&rng, 3);
    ws_aug_params p;
    ws_aug_workspace *ws = NULL;
    size_t n = (size_t)C * W * H;
    float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y);
    fill_random(x, n, &rng);
    ws_aug_workspace_create(&ws, W, H, C, &st);
    /* The fastest of a few runs: the machine may be busy with other work. */
    double fwd = INFINITY, bwd = INFINITY;
    for (int r = 0; r < 20; r++) {
        ws_aug_sample(&p, &rng, W, H, &st);
        double t0 = now();
        ws_aug_forward(&p, x, C, H, W, y, ws, &st);
        double t1 = now();
        ws_aug_backward(&p, y, C, H, W, x, ws, &st);
        double t2 = now();
        fwd = fmin(fwd, t1 - t0);
        bwd = fmin(bwd, t2 - t1);
    }
    printf("224x224x%d (%d threads): forward %.3f ms, backward %.3f ms (fastest of 20)\n", C,
           omp_get_max_threads(), 1e3 * fwd, 1e3 * bwd);
    CHECK(st.code == WS_OK, "%s", st.msg);
    ws_aug_workspace_free(ws);
    free(x);
    free(y);
}

int main(void) {
    test_torchvision_fixture();
    test_identity();
    test_fill_zero();
    test_adjoint(224, 224, 3, 1);
    test_adjoint(224, 224, 1, 2);
    test_adjoint(61, 47, 2, 3);
    test_sample_ranges();
    test_same_transform_and_determinism();
    test_errors();
    time_224(1);
    time_224(3);
    return check_summary();
}
