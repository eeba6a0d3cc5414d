/* test_gemm_bf16.c: the bf16 products with frozen weights (nn/gemm_bf16.h).
 *
 * Rounding: a and B are rounded to bf16 by round to nearest even (checked
 * bit for bit through products with an identity matrix, ties included).
 * Error: with u = 2^-8 (bf16) and g = K' 2^-24 / (1 - K' 2^-24) for K' =
 * k + 1 fp32 additions (k products of pairs and the init), each element
 * of c = init + a B satisfies
 *     |c - (init + sum a^ b^)| <= g (|init| + sum |a^ b^|)     (the sum)
 *     |c - (init + sum a b)|   <= (2u + u^2) S + g (|init| + (1 + u)^2 S)
 * with S = sum |a b|, a^ = bf16(a): products of two bf16 values are exact
 * in fp32, so the sum's rounding and the inputs' rounding are all there is
 * (METHOD.md, "bf16 GEMMs"). Threads: 1 and 2 give the same bits. */
#include <cblas.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "nn/base/rng.h"
#include "nn/gemm_bf16.h"

static ws_rng rng;

static float *randoms(size_t n, double lo, double hi) {
    float *x = malloc(n * sizeof *x);
    for (size_t i = 0; i < n; i++) x[i] = (float)(lo + (hi - lo) * ws_rng_uniform(&rng));
    return x;
}

static float bits_float(uint32_t u) {
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static void test_round(void) {
    struct {
        float x, expect;
    } cases[] = {
        {1.0f, 1.0f},
        {bits_float(0x3f808000u), 1.0f},                 /* 1 + 2^-8: a tie, to the even 1 */
        {bits_float(0x3f818000u), bits_float(0x3f820000u)}, /* 1 + 3 2^-8: a tie, up to even */
        {bits_float(0x3f808001u), bits_float(0x3f810000u)}, /* just above the tie: up */
        {-bits_float(0x3f807fffu), -1.0f},               /* just below the tie: down, sign kept */
        {bits_float(0x7f7fffffu), bits_float(0x7f800000u)}, /* FLT_MAX is above bf16's largest + half an ulp */
        {0.0f, 0.0f},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        CHECK(nn_bf16_round(cases[i].x) == cases[i].expect, "bf16 round of %.9g: %.9g, expected %.9g",
              cases[i].x, nn_bf16_round(cases[i].x), cases[i].expect);
    CHECK(isnan(nn_bf16_round(bits_float(0x7f800001u))), "bf16 round of a NaN with a low mantissa is not NaN");
}

/* /proc/cpuinfo's flags name avx512_bf16: -1 when it cannot be read. */
static int cpuinfo_has_bf16(void) {
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f) return -1;
    char line[8192];
    int found = -1;
    while (found < 0 && fgets(line, sizeof line, f))
        if (!strncmp(line, "flags", 5)) found = strstr(line, " avx512_bf16") != NULL;
    fclose(f);
    return found;
}

/* c = init + a B by the kernel on `threads` threads; B [k,n] from b with
 * trans_b. init: bias + res when either is given, else beta * c0. */
static float *run(const float *a, const nn_bf16_matrix *p, int m, const float *bias, const float *res,
                  float beta, const float *c0, int threads) {
    int n = p->n;
    float *c = malloc((size_t)m * n * sizeof *c), *work = malloc(nn_bf16_gemm_work(m, p->k) * sizeof *work);
    memcpy(c, c0, (size_t)m * n * sizeof *c);
    omp_set_num_threads(threads);
    nn_bf16_gemm(c, a, p, m, bias, res, beta, work);
    free(work);
    return c;
}

/* Checks the kernel's c against the two bounds of the file's comment, and
 * 1 thread against 2. */
static void test_product(int m, int k, int n, int trans_b, int with_bias, int with_res, float beta) {
    float *a = randoms((size_t)m * k, -1, 1), *b = randoms((size_t)k * n, -1, 1);
    float *bias = randoms((size_t)n, -1, 1), *res = randoms((size_t)m * n, -1, 1), *c0 = randoms((size_t)m * n, -1, 1);
    ws_status st;
    nn_bf16_matrix p;
    CHECK(nn_bf16_matrix_pack(&p, b, k, n, trans_b, &st) == WS_OK, "%s", st.msg);
    const float *bi = with_bias ? bias : NULL, *re = with_res ? res : NULL;
    float *c1 = run(a, &p, m, bi, re, beta, c0, 1), *c2 = run(a, &p, m, bi, re, beta, c0, 2);
    CHECK(!memcmp(c1, c2, (size_t)m * n * sizeof *c1), "bf16 gemm %dx%dx%d: 1 and 2 threads differ", m, k, n);
    double g = (k + 1) * 0x1p-24 / (1 - (k + 1) * 0x1p-24), u = 0x1p-8;
    double worst_sum = 0, worst_input = 0, worst_rel = 0;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < n; j++) {
            double init = with_bias || with_res ? (with_bias ? bias[j] : 0) + (with_res ? res[(size_t)i * n + j] : 0)
                                                : beta * c0[(size_t)i * n + j];
            double s = 0, s_hat = 0, abs_s = 0, abs_hat = 0;
            for (int q = 0; q < k; q++) {
                float av = a[(size_t)i * k + q], bv = trans_b ? b[(size_t)j * k + q] : b[(size_t)q * n + j];
                double e = (double)av * bv, h = (double)nn_bf16_round(av) * nn_bf16_round(bv);
                s += e, abs_s += fabs(e), s_hat += h, abs_hat += fabs(h);
            }
            double c = c1[(size_t)i * n + j];
            /* each error as a fraction of its bound: at most 1 */
            worst_sum = fmax(worst_sum, fabs(c - (init + s_hat)) / (g * (fabs(init) + abs_hat)));
            double bound = (2 * u + u * u) * abs_s + g * (fabs(init) + (1 + u) * (1 + u) * abs_s);
            worst_input = fmax(worst_input, fabs(c - (init + s)) / bound);
            worst_rel = fmax(worst_rel, fabs(c - (init + s)) / (fabs(init) + abs_s));
        }
    CHECK(worst_sum <= 1, "bf16 gemm %dx%dx%d: the fp32 sum is off by %.3g of its bound", m, k, n, worst_sum);
    CHECK(worst_input <= 1, "bf16 gemm %dx%dx%d: against fp32, %.3g of the bound", m, k, n, worst_input);
    /* the bound is not vacuous: the rounding of the inputs shows (random
     * signs: about u / sqrt(k) of S, far above the sum's g) */
    CHECK(worst_rel > 1e-4 / sqrt(k), "bf16 gemm %dx%dx%d: error %.3g of S, no bf16 rounding seen", m, k, n,
          worst_rel);
    nn_bf16_matrix_free(&p);
    free(a), free(b), free(bias), free(res), free(c0), free(c1), free(c2);
}

/* a @ I = bf16(a) and I @ B = bf16(B) exactly: the rounding of both
 * operands, ties and signs included, bit for bit. */
static void test_identity(void) {
    enum { M = 7, K = 40 };
    float *a = randoms((size_t)M * K, -4, 4), *eye = calloc((size_t)K * K, sizeof *eye);
    float *eye_m = calloc((size_t)M * M, sizeof *eye_m);
    a[0] = bits_float(0x3f808000u);
    a[1] = bits_float(0x3f818000u);
    a[2] = -bits_float(0x3f808000u);
    for (int i = 0; i < K; i++) eye[i * K + i] = 1;
    for (int i = 0; i < M; i++) eye_m[i * M + i] = 1;
    ws_status st;
    nn_bf16_matrix p_eye, p_a;
    CHECK(nn_bf16_matrix_pack(&p_eye, eye, K, K, 0, &st) == WS_OK, "%s", st.msg);
    CHECK(nn_bf16_matrix_pack(&p_a, a, M, K, 0, &st) == WS_OK, "%s", st.msg);
    float *zero = calloc((size_t)K * K, sizeof *zero);
    float *ca = run(a, &p_eye, M, NULL, NULL, 0, zero, 2), *cb = run(eye_m, &p_a, M, NULL, NULL, 0, zero, 2);
    int bad_a = 0, bad_b = 0;
    for (int i = 0; i < M * K; i++) bad_a += ca[i] != nn_bf16_round(a[i]);
    for (int i = 0; i < M * K; i++) bad_b += cb[i] != nn_bf16_round(a[i]);
    CHECK(!bad_a, "bf16 gemm: a @ I differs from bf16(a) in %d of %d values", bad_a, M * K);
    CHECK(!bad_b, "bf16 gemm: I @ B differs from bf16(B) in %d of %d values", bad_b, M * K);
    nn_bf16_matrix_free(&p_eye);
    nn_bf16_matrix_free(&p_a);
    free(a), free(eye), free(eye_m), free(zero), free(ca), free(cb);
}

/* A linear layer's two packings: forward in @ W^T and backward d_out @ W
 * (W [N,K]; w_kn: W [K,N]), each against the same product packed from its
 * plain [k,n] matrix. */
static void test_linear(int w_kn) {
    enum { M = 9, K = 37, N = 70 };
    float *w = randoms((size_t)K * N, -1, 1), *x = randoms((size_t)M * K, -1, 1), *g = randoms((size_t)M * N, -1, 1);
    float *wt = malloc((size_t)K * N * sizeof *wt); /* W as [K,N] (in @ W^T = in @ wt) */
    for (int j = 0; j < N; j++)
        for (int q = 0; q < K; q++) wt[(size_t)q * N + j] = w_kn ? w[(size_t)q * N + j] : w[(size_t)j * K + q];
    float *wn = malloc((size_t)K * N * sizeof *wn); /* W as [N,K] (d_out @ W = d_out @ wn) */
    for (int j = 0; j < N; j++)
        for (int q = 0; q < K; q++) wn[(size_t)j * K + q] = wt[(size_t)q * N + j];
    ws_status st;
    nn_bf16_linear l;
    nn_bf16_matrix pf, pb;
    CHECK(nn_bf16_linear_pack(&l, w, N, K, w_kn, &st) == WS_OK, "%s", st.msg);
    CHECK(nn_bf16_matrix_pack(&pf, wt, K, N, 0, &st) == WS_OK && nn_bf16_matrix_pack(&pb, wn, N, K, 0, &st) == WS_OK,
          "%s", st.msg);
    float *zero = calloc((size_t)M * (K > N ? K : N), sizeof *zero);
    float *f1 = run(x, &l.forward, M, NULL, NULL, 0, zero, 1), *f2 = run(x, &pf, M, NULL, NULL, 0, zero, 1);
    float *b1 = run(g, &l.backward, M, NULL, NULL, 0, zero, 1), *b2 = run(g, &pb, M, NULL, NULL, 0, zero, 1);
    CHECK(!memcmp(f1, f2, (size_t)M * N * sizeof *f1), "bf16 linear (w_kn %d): forward packing differs", w_kn);
    CHECK(!memcmp(b1, b2, (size_t)M * K * sizeof *b1), "bf16 linear (w_kn %d): backward packing differs", w_kn);
    nn_bf16_linear_free(&l);
    nn_bf16_matrix_free(&pf);
    nn_bf16_matrix_free(&pb);
    free(w), free(x), free(g), free(wt), free(wn), free(zero), free(f1), free(f2), free(b1), free(b2);
}

int main(void) {
    openblas_set_num_threads(1); /* nn/'s ops fork only without OpenBLAS threads (parallel.h) */
    ws_rng_seed(&rng, 7);
    test_round();
    int cpu = cpuinfo_has_bf16();
    if (cpu >= 0)
        CHECK(nn_bf16_available() == cpu, "nn_bf16_available() %d, /proc/cpuinfo says %d", nn_bf16_available(), cpu);
    if (!nn_bf16_available()) {
        printf("this CPU has no AVX512_BF16: the kernel's checks cannot run here\n");
        return check_summary();
    }
    test_identity();
    /* tails: rows not a multiple of the tile's 6, odd k, columns past one
     * panel of 64 and not a multiple of 16 */
    for (int trans_b = 0; trans_b < 2; trans_b++) {
        test_product(1, 1, 1, trans_b, 0, 0, 0);
        test_product(7, 33, 70, trans_b, 0, 0, 0);
        test_product(13, 64, 130, trans_b, 1, 0, 0);
        test_product(13, 31, 200, trans_b, 0, 1, 0);
        test_product(6, 48, 64, trans_b, 1, 1, 0);
        test_product(11, 50, 90, trans_b, 0, 0, 1);
    }
    /* CLIP's sizes: k 768 and 3072 (the bounds' g grows with k) */
    test_product(50, 768, 256, 1, 1, 1, 0);
    test_product(20, 3072, 96, 0, 0, 0, 1);
    test_linear(0);
    test_linear(1);
    return check_summary();
}
