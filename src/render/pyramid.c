/* pyramid.c: Gaussian blur and 2 x 2 pooling (see pyramid.h). Every output
 * pixel is computed by one thread in a fixed order: the bits do not depend
 * on the thread count. */
#include <math.h>
#include <stddef.h>
#include "render/pyramid.h"
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

void ws_blur_forward(const ws_blur_kernel *g, const double *in, double *out, double *tmp, int w, int h) {
    const int R = g->radius;
    const double *k = g->k + R;
#pragma omp parallel for if (nn_fork((size_t)w * h))
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double s = 0;
            for (int t = j - R < 0 ? -j : -R; t <= R && j + t < w; t++) s += k[t] * in[(size_t)i * w + j + t];
            tmp[(size_t)i * w + j] = s;
        }
#pragma omp parallel for if (nn_fork((size_t)w * h))
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double s = 0;
            for (int t = i - R < 0 ? -i : -R; t <= R && i + t < h; t++) s += k[t] * tmp[(size_t)(i + t) * w + j];
            out[(size_t)i * w + j] = s;
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
