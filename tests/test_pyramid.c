/* test_pyramid.c: render/pyramid.h. The separable blur against its
 * definition, summed per pixel over the taps in order (rows, then
 * columns), bit for bit: at every size the borders cut the taps
 * differently (images narrower than the kernel included), in place and
 * not, on images large enough for the blur to run on a team of threads;
 * and against the 2-D kernel of reference_pyramid.h to rounding. The
 * pooling against the reference's, bit for bit, and its backward pass as
 * its adjoint: <pool(x), y> = <x, pool_backward(y)>. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "reference_pyramid.h"
#include "nn/base/rng.h"
#include "render/pyramid.h"

/* out = G * in, each pass a sum over the taps inside the image, t
 * ascending, per pixel. */
static void plain_blur(const ws_blur_kernel *g, const double *in, double *out, int w, int h) {
    const int R = g->radius;
    const double *k = g->k + R;
    double *tmp = malloc((size_t)w * h * sizeof *tmp);
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double s = 0;
            for (int t = -R; t <= R; t++)
                if (j + t >= 0 && j + t < w) s += k[t] * in[(size_t)i * w + j + t];
            tmp[(size_t)i * w + j] = s;
        }
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double s = 0;
            for (int t = -R; t <= R; t++)
                if (i + t >= 0 && i + t < h) s += k[t] * tmp[(size_t)(i + t) * w + j];
            out[(size_t)i * w + j] = s;
        }
    free(tmp);
}

int main(void) {
    static const int sizes[][2] = {{1, 1}, {2, 5}, {7, 3}, {8, 8}, {13, 6}, {50, 37}, {224, 224}, {301, 2}};
    static const double sigmas[] = {0.5, 1.0, 2.0};
    ws_rng rng;
    ws_rng_seed(&rng, 7);
    for (size_t si = 0; si < sizeof sigmas / sizeof *sigmas; si++) {
        ws_blur_kernel g;
        CHECK(ws_blur_kernel_init(&g, sigmas[si]) == 0, "sigma %g: a kernel", sigmas[si]);
        for (size_t z = 0; z < sizeof sizes / sizeof *sizes; z++) {
            const int w = sizes[z][0], h = sizes[z][1];
            const size_t n = (size_t)w * h;
            double *in = malloc(n * sizeof *in), *out = malloc(n * sizeof *out), *tmp = malloc(n * sizeof *tmp);
            double *want = malloc(n * sizeof *want), *ref = malloc(n * sizeof *ref);
            for (size_t p = 0; p < n; p++) in[p] = ws_rng_uniform(&rng) < 0.2 ? 1 + ws_rng_uniform(&rng) : 0;
            plain_blur(&g, in, want, w, h);
            ws_blur_forward(&g, in, out, tmp, w, h);
            CHECK(!memcmp(out, want, n * sizeof *out), "sigma %g, %d x %d: the sums of the definition, bit for bit",
                  sigmas[si], w, h);
            ws_blur_forward(&g, in, in, tmp, w, h); /* in place */
            CHECK(!memcmp(in, want, n * sizeof *in), "sigma %g, %d x %d, in place: the same bits", sigmas[si], w, h);
            /* the definition against the 2-D kernel, on a fresh image */
            double worst = 0, scale = 0;
            for (size_t p = 0; p < n; p++) in[p] = (double)((p * 2654435761u) % 97) / 97.0;
            plain_blur(&g, in, want, w, h);
            ref_blur(in, w, h, sigmas[si], ref);
            for (size_t p = 0; p < n; p++) {
                worst = fmax(worst, fabs(want[p] - ref[p]));
                scale = fmax(scale, fabs(ref[p]));
            }
            CHECK(worst <= 1e-12 * fmax(scale, 1), "sigma %g, %d x %d: the 2-D kernel's blur within %g", sigmas[si], w,
                  h, worst);
            if (si == 0) { /* the pooling, once per size */
                const int w2 = (w + 1) / 2, h2 = (h + 1) / 2;
                double *pooled = malloc((size_t)w2 * h2 * sizeof *pooled), *y = malloc((size_t)w2 * h2 * sizeof *y);
                ref_pool(in, w, h, ref);
                ws_pool2_forward(in, w, h, pooled);
                CHECK(!memcmp(pooled, ref, (size_t)w2 * h2 * sizeof *ref), "%d x %d: pooled as the reference, bit for bit",
                      w, h);
                for (int p = 0; p < w2 * h2; p++) y[p] = ws_rng_normal(&rng);
                memset(out, 0, n * sizeof *out);
                ws_pool2_backward(y, w, h, out);
                double forward = 0, backward = 0;
                for (int p = 0; p < w2 * h2; p++) forward += pooled[p] * y[p];
                for (size_t p = 0; p < n; p++) backward += in[p] * out[p];
                CHECK(fabs(forward - backward) <= 1e-12 * (1 + fabs(forward)),
                      "%d x %d: the pooling's backward is its adjoint (%.17g, %.17g)", w, h, forward, backward);
                free(pooled);
                free(y);
            }
            free(in);
            free(out);
            free(tmp);
            free(want);
            free(ref);
        }
    }
    return check_summary();
}
