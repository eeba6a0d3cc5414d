/* pyramid.c: Gaussian blur and 2 x 2 pooling (see pyramid.h). Every output
 * pixel is computed by one thread in a fixed order: the bits do not depend
 * on the thread count. */
#include <math.h>
#include <stddef.h>
#include "render/pyramid.h"
#include "nn/fastmath.h"
#include "nn/parallel.h"

int ws_blur_kernel_init(ws_blur_kernel *g, double sigma) {
    if (!(sigma > 0) || ceil(3 * sigma) > WS_BLUR_MAX_RADIUS) return -1;
    g->radius = (int)ceil(3 * sigma);
    double sum = 0;
    for (int t = -g->radius; t <= g->radius; t++)
        sum += g->k[t + g->radius] = exp(-t * t / (2 * sigma * sigma));
    for (int t = 0; t <= 2 * g->radius; t++) g->k[t] /= sum;
    return 0;
}

/* The taps of kernel k (centred) at position `at` of a row of n samples:
 * the sum over the taps inside the row, t ascending from -R, from 0. */
NN_INLINE double taps(const double *k, int R, const double *x, int at, int n) {
    double s = 0;
    for (int t = at - R < 0 ? -at : -R; t <= R && at + t < n; t++) s += k[t] * x[at + t];
    return s;
}

/* The blur's passes, a row of output at a time, as sums over the taps t
 * ascending from 0, so every pixel gets the bits of taps(): where all taps
 * are inside the image, a pass over the row per tap, which vectorises over
 * the row. src/ is compiled without contracting a * b + c into a
 * multiply-add, so the wider clones (nn/fastmath.h) give the same bits as
 * the plain x86-64 code. */
NN_SIMD_CLONES static void blur_row(const double *k, int R, const double *restrict in, double *restrict out, int w) {
    const int lo = R < w ? R : w, hi = w - R > lo ? w - R : lo;
    for (int j = 0; j < lo; j++) out[j] = taps(k, R, in, j, w);
    #pragma omp simd
    for (int j = lo; j < hi; j++) out[j] = 0;
    for (int t = -R; t <= R; t++) {
        const double kt = k[t];
        #pragma omp simd
        for (int j = lo; j < hi; j++) out[j] += kt * in[j + t];
    }
    for (int j = hi; j < w; j++) out[j] = taps(k, R, in, j, w);
}

/* Row i of the vertical pass over tmp (h x w). */
NN_SIMD_CLONES static void blur_column_row(const double *k, int R, const double *restrict tmp, double *restrict out,
                                           int i, int w, int h) {
    const int t0 = i - R < 0 ? -i : -R, t1 = i + R < h ? R : h - 1 - i;
    #pragma omp simd
    for (int j = 0; j < w; j++) out[j] = 0;
    for (int t = t0; t <= t1; t++) {
        const double kt = k[t], *src = tmp + (ptrdiff_t)(i + t) * w;
        #pragma omp simd
        for (int j = 0; j < w; j++) out[j] += kt * src[j];
    }
}

void ws_blur_forward(const ws_blur_kernel *g, const double *in, double *out, double *tmp, int w, int h) {
    const int R = g->radius;
    const double *k = g->k + R;
    /* one team for both passes: the rows of a column's taps are done when
     * the first loop's threads meet at its end */
#pragma omp parallel if (nn_fork((size_t)w * h))
    {
#pragma omp for
        for (int i = 0; i < h; i++) blur_row(k, R, in + (size_t)i * w, tmp + (size_t)i * w, w);
#pragma omp for
        for (int i = 0; i < h; i++) blur_column_row(k, R, tmp, out + (size_t)i * w, i, w, h);
    }
}

void ws_blur_repeat_forward(const ws_blur_kernel *g, const double *in, double *out, double *tmp, int w, int h) {
    const size_t n = (size_t)w * h;
    const int R = g->radius;
#pragma omp parallel for if (nn_fork(n))
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double sum = 0;
            for (int t = -R; t <= R; t++) sum += g->k[t + R] * in[(size_t)i * w + ws_repeat_index(j + t, w)];
            tmp[(size_t)i * w + j] = sum;
        }
#pragma omp parallel for if (nn_fork(n))
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double sum = 0;
            for (int t = -R; t <= R; t++) sum += g->k[t + R] * tmp[(size_t)ws_repeat_index(i + t, h) * w + j];
            out[(size_t)i * w + j] = sum;
        }
}

/* Number of pixels of a w x h image that pooled cell (i, j) covers. */
static int cell_count(int w, int h, int i, int j) {
    return (2 * i + 1 < h ? 2 : 1) * (2 * j + 1 < w ? 2 : 1);
}

void ws_pool2_forward(const double *in, int w, int h, double *out) {
    int wo = (w + 1) / 2, ho = (h + 1) / 2;
#pragma omp parallel for if (nn_fork((size_t)w * h))
    for (int i = 0; i < ho; i++)
        for (int j = 0; j < wo; j++) {
            double sum = 0;
            for (int a = 2 * i; a < 2 * i + 2 && a < h; a++)
                for (int b = 2 * j; b < 2 * j + 2 && b < w; b++) sum += in[(size_t)a * w + b];
            out[(size_t)i * wo + j] = sum / cell_count(w, h, i, j);
        }
}

void ws_pool2_backward(const double *dout, int w, int h, double *din) {
    int wo = (w + 1) / 2;
#pragma omp parallel for if (nn_fork((size_t)w * h))
    for (int a = 0; a < h; a++)
        for (int b = 0; b < w; b++)
            din[(size_t)a * w + b] += dout[(size_t)(a / 2) * wo + b / 2] / cell_count(w, h, a / 2, b / 2);
}
