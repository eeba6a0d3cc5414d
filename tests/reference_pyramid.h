/* reference_pyramid.h: 2 x 2 average pooling and the Gaussian blur of
 * render/pyramid.h written out the slow way (a 2-D kernel), for the tests
 * of the losses built on them (test_edges.c, test_lines.c). */
#ifndef WS_REFERENCE_PYRAMID_H
#define WS_REFERENCE_PYRAMID_H
#include <math.h>

/* out: ceil(h/2) x ceil(w/2); a cell averages the pixels it has. */
static void ref_pool(const double *in, int w, int h, double *out) {
    int w2 = (w + 1) / 2, h2 = (h + 1) / 2;
    for (int i = 0; i < h2; i++)
        for (int j = 0; j < w2; j++) {
            double sum = 0;
            int count = 0;
            for (int a = 2 * i; a <= 2 * i + 1; a++)
                for (int b = 2 * j; b <= 2 * j + 1; b++)
                    if (a < h && b < w) sum += in[a * w + b], count++;
            out[i * w2 + j] = sum / count;
        }
}

/* out = G * in, kernel exp(-t^2 / (2 sigma^2)) for |t| <= ceil(3 sigma)
 * normalised per axis, zero outside; out must not be in. */
static void ref_blur(const double *in, int w, int h, double sigma, double *out) {
    const int R = (int)ceil(3 * sigma);
    double k[64], ksum = 0;
    for (int t = -R; t <= R; t++) ksum += k[t + R] = exp(-t * t / (2 * sigma * sigma));
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double g = 0;
            for (int a = -R; a <= R; a++)
                for (int b = -R; b <= R; b++)
                    if (i + a >= 0 && i + a < h && j + b >= 0 && j + b < w)
                        g += k[a + R] * k[b + R] / (ksum * ksum) * in[(i + a) * w + j + b];
            out[i * w + j] = g;
        }
}

#endif
