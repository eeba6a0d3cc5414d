/* bench_splat.c: cost and error of the splatting's cut-off (bench.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench/bench.h"
#include "render/splat.h"
#include "base/timing.h"

const double ws_bench_cutoffs[WS_BENCH_CUTOFFS] = {2, 3, 4, 5, INFINITY};

double ws_bench_pixel_visits(const ws_camera *cam, const double *mu, int n, double radius,
                             double cutoff, int *drawn) {
    double visits = 0;
    *drawn = 0;
    for (int k = 0; k < n; k++) {
        double c[3];
        ws_camera_to_cam(cam, mu + 3 * k, c);
        double u, v, d = ws_camera_project(cam, c, &u, &v), w = cam->width, h = cam->height;
        if (!(d > 1e-3)) continue;
        if (isfinite(cutoff)) {
            u -= WS_PIXEL_CENTER; /* in pixel indices, as the splat's boxes */
            v -= WS_PIXEL_CENTER;
            double reach = cutoff * cam->focal * radius / d;
            w = fmin(cam->width - 1, floor(u + reach)) - fmax(0, ceil(u - reach)) + 1;
            h = fmin(cam->height - 1, floor(v + reach)) - fmax(0, ceil(v - reach)) + 1;
        }
        if (w > 0 && h > 0) {
            visits += w * h;
            ++*drawn;
        }
    }
    return visits;
}

/* The Gaussians of a random sketch, at least `want` of them (curves of 80
 * Gaussians or so, as many as needed). */
static int sketch_gaussians(const double center[3], int want, ws_curves *c, ws_gaussians *g,
                            ws_status *st) {
    for (int curves = want / 80 + 1;; curves *= 2) {
        ws_curves_free(c);
        if (ws_bench_sketch(c, curves, center, 0.8, 1.28, 5, st) || ws_curves_sample(c, g, st))
            return st->code;
        if (g->n >= want) return WS_OK;
    }
}

int ws_bench_splat(const ws_camera *cam, const double center[3], int gaussians, int rounds,
                   ws_bench_splat_row *row, ws_status *st) {
    memset(row, 0, sizeof *row);
    row->gaussians = gaussians;
    ws_curves c = {0};
    ws_gaussians g = {0};
    ws_splat *splat = NULL;
    size_t pixels = (size_t)cam->width * cam->height;
    double *alpha = NULL, *dmu = NULL, *dalpha = NULL;
    int rc = sketch_gaussians(center, gaussians, &c, &g, st);
    if (!rc) rc = ws_splat_create(&splat, cam->width, cam->height, st);
    if (!rc && (!(alpha = ws_malloc(WS_BENCH_CUTOFFS * pixels * sizeof(double), "benchmark images", st)) ||
                !(dmu = ws_malloc(WS_BENCH_CUTOFFS * (size_t)gaussians * 3 * sizeof(double),
                                  "benchmark gradients", st)) ||
                !(dalpha = ws_malloc(pixels * sizeof(double), "benchmark gradients", st))))
        rc = st->code;
    if (rc) goto done;
    ws_rng rng;
    ws_rng_seed(&rng, 11);
    for (size_t p = 0; p < pixels; p++) dalpha[p] = 2 * ws_rng_uniform(&rng) - 1;
    ws_splat_options so;
    ws_splat_options_default(&so);
    for (int k = 0; k < WS_BENCH_CUTOFFS; k++) {
        row->forward[k] = row->backward[k] = INFINITY;
        int drawn;
        row->pixel_visits[k] = ws_bench_pixel_visits(cam, g.mu, gaussians, c.thickness, ws_bench_cutoffs[k], &drawn);
    }
    /* the exact sum costs pixels x Gaussians: one round of it is plenty */
    for (int r = 0; r < rounds; r++)
        for (int k = 0; k < WS_BENCH_CUTOFFS; k++) {
            if (r > 0 && isinf(ws_bench_cutoffs[k]) && row->forward[k] + row->backward[k] > 2.0) continue;
            so.cutoff = ws_bench_cutoffs[k];
            double t0 = ws_seconds();
            if (ws_splat_forward(splat, cam, g.mu, gaussians, c.thickness, &so, alpha + k * pixels, st))
                goto fail;
            double t1 = ws_seconds();
            if (ws_splat_backward(splat, dalpha, dmu + (size_t)k * gaussians * 3, st)) goto fail;
            double t2 = ws_seconds();
            row->forward[k] = fmin(row->forward[k], t1 - t0);
            row->backward[k] = fmin(row->backward[k], t2 - t1);
        }
    const int ex = WS_BENCH_CUTOFFS - 1;
    const double *alpha_ex = alpha + ex * pixels, *dmu_ex = dmu + (size_t)ex * gaussians * 3;
    double gmax = 0, gsum = 0;
    for (size_t i = 0; i < (size_t)gaussians * 3; i++) {
        gmax = fmax(gmax, fabs(dmu_ex[i]));
        gsum += fabs(dmu_ex[i]);
    }
    for (int k = 0; k < WS_BENCH_CUTOFFS; k++) {
        const double *a = alpha + k * pixels, *d = dmu + (size_t)k * gaussians * 3;
        double amax = 0, asum = 0, dmax = 0, dsum = 0;
        for (size_t p = 0; p < pixels; p++) {
            amax = fmax(amax, fabs(a[p] - alpha_ex[p]));
            asum += fabs(a[p] - alpha_ex[p]);
        }
        for (size_t i = 0; i < (size_t)gaussians * 3; i++) {
            dmax = fmax(dmax, fabs(d[i] - dmu_ex[i]));
            dsum += fabs(d[i] - dmu_ex[i]);
        }
        row->alpha_max[k] = amax;
        row->alpha_mean[k] = asum / pixels;
        row->grad_max[k] = gmax > 0 ? dmax / gmax : 0;
        row->grad_mean[k] = gsum > 0 ? dsum / gsum : 0;
    }
    goto done;
fail:
    rc = st->code;
done:
    ws_curves_free(&c);
    ws_gaussians_free(&g);
    ws_splat_free(splat);
    free(alpha);
    free(dmu);
    free(dalpha);
    return rc;
}
