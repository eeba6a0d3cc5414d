/* test_splat.c: the splatting rasteriser against a direct summation written
 * here, against the reference fixture of tools/reference_splat.py, its
 * gradients against central finite differences (double), the stiff cases of
 * METHOD.md section 3, the far limit, and determinism (same bits for 1 and
 * 2 threads). */
#include <cJSON.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "nn/base/bytes.h"
#include "check.h"
#include "render/curves.h"
#include "objective/loss_l2.h"
#include "render/splat.h"

/* A camera at `eye` looking at `target` (+y up), width x height. */
static ws_camera look_at(const double eye[3], const double target[3], int width, int height) {
    double z[3], x[3], y[3], up[3] = {0, 1, 0}, len;
    for (int k = 0; k < 3; k++) z[k] = eye[k] - target[k]; /* the camera looks down -z */
    len = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int k = 0; k < 3; k++) z[k] /= len;
    x[0] = up[1] * z[2] - up[2] * z[1];
    x[1] = up[2] * z[0] - up[0] * z[2];
    x[2] = up[0] * z[1] - up[1] * z[0];
    len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int k = 0; k < 3; k++) x[k] /= len;
    y[0] = z[1] * x[2] - z[2] * x[1];
    y[1] = z[2] * x[0] - z[0] * x[2];
    y[2] = z[0] * x[1] - z[1] * x[0];
    double c2w[4][4] = {{x[0], y[0], z[0], eye[0]},
                        {x[1], y[1], z[1], eye[1]},
                        {x[2], y[2], z[2], eye[2]},
                        {0, 0, 0, 1}};
    ws_camera cam;
    ws_status st;
    if (ws_camera_init(&cam, c2w, 0.69, width, height, "test camera", &st))
        fprintf(stderr, "camera: %s\n", st.msg);
    return cam;
}

/* METHOD.md section 3 written out directly: every Gaussian in front of the camera, every
 * pixel, w = exp(-r^2 / (2 sigma^2)) when r <= cutoff sigma. */
static void direct_alpha(const ws_camera *cam, const double *mu, int n, double radius,
                         double cutoff, double *alpha) {
    int W = cam->width, H = cam->height;
    for (int p = 0; p < W * H; p++) alpha[p] = 1.0;
    for (int k = 0; k < n; k++) {
        double c[3];
        ws_camera_to_cam(cam, mu + 3 * k, c);
        double d = -c[2];
        if (d <= 1e-3) continue;
        double u = W / 2.0 + cam->focal * c[0] / d, v = H / 2.0 - cam->focal * c[1] / d;
        double sigma = cam->focal * radius / d;
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++) {
                double r2 = (j + 0.5 - u) * (j + 0.5 - u) + (i + 0.5 - v) * (i + 0.5 - v);
                if (r2 <= cutoff * cutoff * sigma * sigma)
                    alpha[i * W + j] *= 1.0 - exp(-r2 / (2 * sigma * sigma));
            }
    }
    for (int p = 0; p < W * H; p++) alpha[p] = 1.0 - alpha[p];
}

/* Sum over pixels of the omitted weights: a bound on |alpha_cut - alpha_exact|
 * since alpha is 1-Lipschitz in each w (|d alpha / d w| <= 1). */
static void omitted_weight(const ws_camera *cam, const double *mu, int n, double radius,
                           double cutoff, double *bound) {
    int W = cam->width, H = cam->height;
    for (int p = 0; p < W * H; p++) bound[p] = 0;
    for (int k = 0; k < n; k++) {
        double c[3];
        ws_camera_to_cam(cam, mu + 3 * k, c);
        double d = -c[2], u = W / 2.0 + cam->focal * c[0] / d, v = H / 2.0 - cam->focal * c[1] / d;
        double sigma = cam->focal * radius / d;
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++) {
                double r2 = (j + 0.5 - u) * (j + 0.5 - u) + (i + 0.5 - v) * (i + 0.5 - v);
                if (r2 > cutoff * cutoff * sigma * sigma) bound[i * W + j] += exp(-r2 / (2 * sigma * sigma));
            }
    }
}

static double max_abs_diff(const double *a, const double *b, int n) {
    double m = 0;
    for (int k = 0; k < n; k++) m = fmax(m, fabs(a[k] - b[k]));
    return m;
}

static int all_finite(const double *a, int n) {
    for (int k = 0; k < n; k++)
        if (!isfinite(a[k])) return 0;
    return 1;
}

static void random_mu(ws_rng *rng, double *mu, int n, double spread) {
    for (int k = 0; k < 3 * n; k++) mu[k] = spread * (2 * ws_rng_uniform(rng) - 1);
}

/* L = sum alpha * weights. */
static double weighted_loss(ws_splat *s, const ws_camera *cam, const double *mu, int n,
                            double radius, const ws_splat_options *opt, const double *weights,
                            double *alpha) {
    ws_status st;
    if (ws_splat_forward(s, cam, mu, n, radius, opt, alpha, &st)) {
        fprintf(stderr, "forward: %s\n", st.msg);
        return NAN;
    }
    double L = 0;
    for (int p = 0; p < cam->width * cam->height; p++) L += alpha[p] * weights[p];
    return L;
}

/* dL/dmu of L = sum alpha * weights against central differences for the
 * Gaussians in `which`; returns the worst relative error (floor: 1e-4 of the
 * largest gradient). */
static double check_dmu_fd(const char *what, const ws_camera *cam, double *mu, int n,
                           double radius, const ws_splat_options *opt, const int *which,
                           int nwhich, double h, double tol) {
    ws_status st;
    ws_splat *s;
    int P = cam->width * cam->height;
    double *alpha = malloc(sizeof(double) * P), *weights = malloc(sizeof(double) * P);
    double *dmu = malloc(sizeof(double) * 3 * (n ? n : 1));
    ws_rng rng;
    ws_rng_seed(&rng, 3);
    for (int p = 0; p < P; p++) weights[p] = ws_rng_normal(&rng);
    ws_splat_create(&s, cam->width, cam->height, &st);
    weighted_loss(s, cam, mu, n, radius, opt, weights, alpha);
    CHECK(ws_splat_backward(s, weights, dmu, &st) == WS_OK, "%s: backward: %s", what, st.msg);
    CHECK(all_finite(dmu, 3 * n), "%s: dmu finite", what);
    double gmax = 0, worst = 0;
    for (int k = 0; k < 3 * n; k++) gmax = fmax(gmax, fabs(dmu[k]));
    for (int q = 0; q < nwhich; q++)
        for (int x = 0; x < 3; x++) {
            int k = 3 * which[q] + x;
            double saved = mu[k];
            mu[k] = saved + h;
            double Lp = weighted_loss(s, cam, mu, n, radius, opt, weights, alpha);
            mu[k] = saved - h;
            double Lm = weighted_loss(s, cam, mu, n, radius, opt, weights, alpha);
            mu[k] = saved;
            double fd = (Lp - Lm) / (2 * h);
            double err = fabs(fd - dmu[k]) / fmax(fmax(fabs(fd), fabs(dmu[k])), 1e-4 * gmax);
            if (gmax == 0) err = fabs(fd - dmu[k]);
            worst = fmax(worst, err);
            CHECK(err <= tol, "%s: dmu[%d][%d] %.10g vs FD %.10g", what, which[q], x, dmu[k], fd);
        }
    ws_splat_free(s);
    free(alpha);
    free(weights);
    free(dmu);
    return worst;
}

static void test_fixture(void) {
    ws_status st;
    unsigned char *text;
    size_t len;
    const char *path = "tests/fixtures/splat_ref.json";
    if (ws_read_file(path, 1 << 20, &text, &len, &st)) {
        CHECK(0, "%s", st.msg);
        return;
    }
    cJSON *root = cJSON_ParseWithLength((const char *)text, len);
    free(text);
    CHECK(root != NULL, "fixture parses");
    if (!root) return;
    int W = cJSON_GetObjectItem(root, "width")->valueint, H = cJSON_GetObjectItem(root, "height")->valueint;
    double radius = cJSON_GetObjectItem(root, "radius")->valuedouble;
    double angle = cJSON_GetObjectItem(root, "camera_angle_x")->valuedouble, c2w[4][4];
    const cJSON *m = cJSON_GetObjectItem(root, "transform_matrix");
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) c2w[i][j] = cJSON_GetArrayItem(cJSON_GetArrayItem(m, i), j)->valuedouble;
    const cJSON *jmu = cJSON_GetObjectItem(root, "mu"), *jdmu = cJSON_GetObjectItem(root, "dmu");
    int n = cJSON_GetArraySize(jmu);
    double *mu = malloc(sizeof(double) * 3 * n), *want_dmu = malloc(sizeof(double) * 3 * n);
    double *dmu = malloc(sizeof(double) * 3 * n);
    double *alpha = malloc(sizeof(double) * W * H), *want = malloc(sizeof(double) * W * H);
    double *dalpha = malloc(sizeof(double) * W * H);
    for (int k = 0; k < n; k++)
        for (int x = 0; x < 3; x++) {
            mu[3 * k + x] = cJSON_GetArrayItem(cJSON_GetArrayItem(jmu, k), x)->valuedouble;
            want_dmu[3 * k + x] = cJSON_GetArrayItem(cJSON_GetArrayItem(jdmu, k), x)->valuedouble;
        }
    const cJSON *ja = cJSON_GetObjectItem(root, "alpha"), *jd = cJSON_GetObjectItem(root, "dalpha");
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            want[i * W + j] = cJSON_GetArrayItem(cJSON_GetArrayItem(ja, i), j)->valuedouble;
            dalpha[i * W + j] = cJSON_GetArrayItem(cJSON_GetArrayItem(jd, i), j)->valuedouble;
        }
    cJSON_Delete(root);
    ws_camera cam;
    CHECK(ws_camera_init(&cam, c2w, angle, W, H, path, &st) == WS_OK, "fixture camera");
    ws_splat *s;
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    opt.cutoff = INFINITY;
    ws_splat_create(&s, W, H, &st);
    CHECK(ws_splat_forward(s, &cam, mu, n, radius, &opt, alpha, &st) == WS_OK, "fixture forward");
    CHECK(ws_splat_backward(s, dalpha, dmu, &st) == WS_OK, "fixture backward");
    double ea = max_abs_diff(alpha, want, W * H), gmax = 0, eg = 0;
    for (int k = 0; k < 3 * n; k++) gmax = fmax(gmax, fabs(want_dmu[k]));
    eg = max_abs_diff(dmu, want_dmu, 3 * n) / gmax;
    CHECK(ea < 1e-12, "fixture alpha within 1e-12: %g", ea);
    CHECK(alpha[5 * W + 12] == 1.0, "exact hit on pixel (5, 12): alpha %.17g", alpha[5 * W + 12]);
    CHECK(eg < 1e-10, "fixture dmu within 1e-10 relative: %g", eg);
    CHECK(dmu[21] == 0 && dmu[22] == 0 && dmu[23] == 0, "Gaussian behind the camera: dmu 0");
    printf("fixture (tools/reference_splat.py): max |alpha - ref| %.2e, max |dmu - ref| / max %.2e\n",
           ea, eg);
    ws_splat_free(s);
    free(mu);
    free(want_dmu);
    free(dmu);
    free(alpha);
    free(want);
    free(dalpha);
}

static void test_forward_direct(void) {
    ws_status st;
    ws_rng rng;
    ws_rng_seed(&rng, 1);
    const double eye[3] = {2.5, 1.5, 3.0}, target[3] = {0, 0, 0};
    const int sizes[2][2] = {{64, 64}, {50, 37}};
    for (int z = 0; z < 2; z++) {
        int W = sizes[z][0], H = sizes[z][1], n = 300;
        ws_camera cam = look_at(eye, target, W, H);
        double *mu = malloc(sizeof(double) * 3 * n), *a = malloc(sizeof(double) * W * H);
        double *ref = malloc(sizeof(double) * W * H), *bound = malloc(sizeof(double) * W * H);
        random_mu(&rng, mu, n, 0.6);
        ws_splat *s;
        ws_splat_options opt;
        ws_splat_options_default(&opt);
        ws_splat_create(&s, W, H, &st);
        double radius = 0.03;
        opt.cutoff = INFINITY;
        CHECK(ws_splat_forward(s, &cam, mu, n, radius, &opt, a, &st) == WS_OK, "forward: %s", st.msg);
        direct_alpha(&cam, mu, n, radius, INFINITY, ref);
        double e_inf = max_abs_diff(a, ref, W * H);
        CHECK(e_inf < 1e-12, "%dx%d cutoff inf vs direct sum: %g", W, H, e_inf);
        double amax = 0;
        for (int p = 0; p < W * H; p++) amax = fmax(amax, a[p]);
        CHECK(amax > 0.5, "the Gaussians are in view (max alpha %g)", amax);

        opt.cutoff = 4;
        ws_splat_forward(s, &cam, mu, n, radius, &opt, a, &st);
        double *cut = malloc(sizeof(double) * W * H);
        direct_alpha(&cam, mu, n, radius, 4, cut);
        double e_cut = max_abs_diff(a, cut, W * H);
        CHECK(e_cut < 1e-12, "%dx%d cutoff 4 vs direct sum with the same cut-off: %g", W, H, e_cut);
        omitted_weight(&cam, mu, n, radius, 4, bound);
        int within = 1;
        double worst = 0;
        for (int p = 0; p < W * H; p++) {
            worst = fmax(worst, fabs(a[p] - ref[p]));
            if (fabs(a[p] - ref[p]) > bound[p] + 1e-12) within = 0;
        }
        CHECK(within, "%dx%d cutoff 4: |alpha - exact| <= sum of omitted w at every pixel", W, H);
        CHECK(worst < 1e-2 && worst > 0, "%dx%d cutoff 4 error %g, small and non-zero", W, H, worst);
        printf("%dx%d, %d Gaussians: cutoff inf vs direct %.1e; cutoff 4 vs exact max %.2e\n", W, H,
               n, e_inf, worst);
        ws_splat_free(s);
        free(mu);
        free(a);
        free(ref);
        free(bound);
        free(cut);
    }
}

static void test_gradients(void) {
    ws_rng rng;
    ws_rng_seed(&rng, 2);
    const double eye[3] = {-2.0, 1.0, 3.5}, target[3] = {0, 0.1, 0};
    ws_camera cam = look_at(eye, target, 48, 40);
    int n = 150;
    double *mu = malloc(sizeof(double) * 3 * n);
    random_mu(&rng, mu, n, 0.5);
    int which[12];
    for (int q = 0; q < 12; q++) which[q] = (int)ws_rng_below(&rng, n);
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    opt.cutoff = INFINITY;
    double worst = check_dmu_fd("dmu, cutoff inf", &cam, mu, n, 0.04, &opt, which, 12, 1e-6, 1e-5);
    printf("dL/dmu vs central FD (cutoff inf): worst relative error %.2e\n", worst);
    free(mu);
}

/* Control points with the sample parameters held fixed: mu(P) at g->t. */
static void mu_at_fixed_t(const ws_curves *c, const ws_gaussians *g, double *mu) {
    for (int k = 0; k < g->n; k++) ws_curve_point(c, g->curve[k], g->t[k], mu + 3 * k);
}

/* L(P) through sampling (t fixed), splatting and the l2 loss against
 * `photo` (3 x W x H); returns L and, when dP is given, dL/dP. */
static double curve_loss(ws_splat *s, const ws_camera *cam, const ws_curves *c,
                         const ws_gaussians *g, const ws_splat_options *opt, const float *photo,
                         double *dP) {
    ws_status st;
    int P = cam->width * cam->height;
    double *mu = malloc(sizeof(double) * 3 * g->n), *alpha = malloc(sizeof(double) * P);
    mu_at_fixed_t(c, g, mu);
    double L = NAN;
    if (!ws_splat_forward(s, cam, mu, g->n, c->thickness, opt, alpha, &st)) {
        L = ws_loss_l2_forward(alpha, photo, P);
        if (dP) {
            double *dalpha = calloc(P, sizeof(double)), *dmu = malloc(sizeof(double) * 3 * g->n);
            ws_loss_l2_backward(alpha, photo, P, 1.0, dalpha);
            if (!ws_splat_backward(s, dalpha, dmu, &st)) ws_curves_backward(c, g, dmu, dP);
            free(dalpha);
            free(dmu);
        }
    }
    free(mu);
    free(alpha);
    return L;
}

static void check_curves_fd(const char *what, const ws_camera *cam, ws_curves *c,
                            const ws_splat_options *opt, const float *photo) {
    ws_status st;
    ws_gaussians g = {0};
    ws_splat *s;
    CHECK(ws_curves_sample(c, &g, &st) == WS_OK, "%s: sample", what);
    ws_splat_create(&s, cam->width, cam->height, &st);
    /* h: the truncation error (h / thickness)^2 / 6 ~ 6e-8 stays below the
     * rounding error of L (~1e-16 L / h) of a smaller step. */
    double *dP = malloc(sizeof(double) * WS_CURVE_FLOATS * c->n), gmax = 0, worst = 0, h = 3e-5;
    curve_loss(s, cam, c, &g, opt, photo, dP);
    CHECK(all_finite(dP, WS_CURVE_FLOATS * c->n), "%s: dL/dP finite", what);
    for (int k = 0; k < WS_CURVE_FLOATS * c->n; k++) gmax = fmax(gmax, fabs(dP[k]));
    CHECK(gmax > 0, "%s: the gradient is not all zero", what);
    for (int k = 0; k < WS_CURVE_FLOATS * c->n; k++) {
        double saved = c->P[k];
        c->P[k] = saved + h;
        double Lp = curve_loss(s, cam, c, &g, opt, photo, NULL);
        c->P[k] = saved - h;
        double Lm = curve_loss(s, cam, c, &g, opt, photo, NULL);
        c->P[k] = saved;
        double fd = (Lp - Lm) / (2 * h);
        double err = fabs(fd - dP[k]) / fmax(fmax(fabs(fd), fabs(dP[k])), 1e-4 * gmax);
        worst = fmax(worst, err);
        CHECK(err < 1e-5, "%s: dP[%d] %.10g vs FD %.10g", what, k, dP[k], fd);
    }
    printf("%s: dL/dP vs central FD, worst relative error %.2e (%d Gaussians)\n", what, worst, g.n);
    free(dP);
    ws_splat_free(s);
    ws_gaussians_free(&g);
}

/* End to end: curves -> Gaussians -> splat -> l2 loss -> dL/dP, including
 * degenerate curves, against a photo with content and a blank one. */
static void test_end_to_end(void) {
    ws_rng rng;
    ws_rng_seed(&rng, 4);
    const double eye[3] = {1.0, 2.0, 3.5}, target[3] = {0, 0, 0};
    int W = 40, H = 40;
    ws_camera cam = look_at(eye, target, W, H);
    ws_curves c;
    ws_status st;
    ws_curves_alloc(&c, 5, &st);
    c.thickness = 0.05;
    c.overlap = 0.5;
    for (int k = 0; k < 36; k++) c.P[k] = 0.4 * ws_rng_normal(&rng);
    for (int k = 36; k < 60; k++) c.P[k] = k < 48 ? 0.1 : -0.2; /* curves 3, 4 degenerate */
    float *photo = malloc(sizeof(float) * 3 * W * H), *blank = calloc(3 * W * H, sizeof(float));
    for (int k = 0; k < 3 * W * H; k++) photo[k] = (float)ws_rng_uniform(&rng);
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    opt.cutoff = INFINITY;
    check_curves_fd("curves with 2 degenerate, random photo", &cam, &c, &opt, photo);
    check_curves_fd("curves, blank target", &cam, &c, &opt, blank);
    free(photo);
    free(blank);
    ws_curves_free(&c);
}

static void test_stiff(void) {
    ws_status st;
    const double eye[3] = {0, 0, 4}, target[3] = {0, 0, 0};
    ws_camera cam = look_at(eye, target, 64, 64);
    double f = cam.focal;
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    opt.cutoff = INFINITY;
    int all[4] = {0, 1, 2, 3};

    /* Exact hit: mu projects onto the centre (32.5, 32.5) of pixel (32, 32),
     * w = 1 there. */
    double hit[6] = {0.5 * 4 / f, -0.5 * 4 / f, 0, 0.3 * 4 / f, -0.2 * 4 / f, 0};
    double radius = 0.9 * 4 / f, a[64 * 64];
    ws_splat *s;
    ws_splat_create(&s, 64, 64, &st);
    ws_splat_forward(s, &cam, hit, 2, radius, &opt, a, &st);
    CHECK(a[32 * 64 + 32] == 1.0, "exact hit: alpha 1 (%.17g)", a[32 * 64 + 32]);
    check_dmu_fd("exact hit", &cam, hit, 2, radius, &opt, all, 2, 1e-6, 1e-5);

    /* sigma 1e-4 px: only the exact hit sees it. */
    double tiny = 1e-4 * 4 / f, dmu[3 * 5000];
    ws_splat_forward(s, &cam, hit, 2, tiny, &opt, a, &st);
    int others = 0;
    for (int p = 0; p < 64 * 64; p++) others += p != 32 * 64 + 32 && a[p] != 0;
    CHECK(a[32 * 64 + 32] == 1.0 && others == 0, "sigma 1e-4 px: alpha 1 on the hit, 0 elsewhere");
    double ones[64 * 64];
    for (int p = 0; p < 64 * 64; p++) ones[p] = 1.0;
    CHECK(ws_splat_backward(s, ones, dmu, &st) == WS_OK && all_finite(dmu, 6),
          "sigma 1e-4 px: finite gradient");
    CHECK(dmu[3] == 0 && dmu[4] == 0 && dmu[5] == 0, "sigma 1e-4 px, off the pixels: gradient 0");

    /* sigma 1e4 px: w close to 1 everywhere; the cut-off box is the image. */
    double huge = 1e4 * 4 / f, b[64 * 64], ref[64 * 64];
    ws_splat_forward(s, &cam, hit, 2, huge, &opt, a, &st);
    direct_alpha(&cam, hit, 2, huge, INFINITY, ref);
    CHECK(max_abs_diff(a, ref, 64 * 64) < 1e-12, "sigma 1e4 px: matches the direct sum");
    opt.cutoff = 4;
    ws_splat_forward(s, &cam, hit, 2, huge, &opt, b, &st);
    CHECK(!memcmp(a, b, sizeof a), "sigma 1e4 px: cut-off 4 covers the image, same as exact");
    CHECK(ws_splat_backward(s, ones, dmu, &st) == WS_OK && all_finite(dmu, 6),
          "sigma 1e4 px: finite gradient");
    /* One Gaussian: with two, T = (1 - w1)(1 - w2) ~ 1e-11 keeps only ~5
     * digits in alpha = 1 - T, too few for a finite difference. The step is
     * 1 world unit (22 px, small against sigma). */
    opt.cutoff = INFINITY;
    check_dmu_fd("sigma 1e4 px", &cam, hit, 1, huge, &opt, all, 1, 1.0, 1e-3);

    /* At the camera plane, behind it, at the near bound: culled. */
    double planes[15] = {0.1, 0.1, 4.0, 0.3, 0, 5.0, 0, 0.2, 4.5, 0, 0, 4 - 1e-3, 0.05, 0.05, 4 - 2e-3};
    double *mu5 = malloc(sizeof(double) * 3 * 5000);
    memcpy(mu5, hit, sizeof hit);
    memcpy(mu5 + 6, planes, sizeof planes);
    ws_splat_forward(s, &cam, hit, 2, radius, &opt, ref, &st);
    CHECK(ws_splat_forward(s, &cam, mu5, 7, radius, &opt, a, &st) == WS_OK && all_finite(a, 64 * 64),
          "Gaussians at and behind the camera: finite");
    double d_near = -(mu5[3 * 6 + 2] - 4);
    CHECK(d_near > 1e-3, "the last Gaussian is just past the near bound (d %g)", d_near);
    CHECK(ws_splat_backward(s, ones, dmu, &st) == WS_OK && all_finite(dmu, 21),
          "culled: finite gradient");
    int zero = 1;
    for (int k = 6; k < 18; k++) zero &= dmu[k] == 0;
    CHECK(zero, "Gaussians at d = 0, d < 0, d <= near: gradient exactly 0");
    CHECK(dmu[18] != 0 && fabs(dmu[18]) < 1e300, "the Gaussian just past the near bound is drawn");
    ws_splat_forward(s, &cam, mu5, 6, radius, &opt, a, &st);
    CHECK(!memcmp(a, ref, sizeof ref), "culled Gaussians leave alpha unchanged");

    /* 5000 Gaussians on the centre of pixel (16, 16): the products
     * underflow, nothing breaks. */
    ws_rng rng;
    ws_rng_seed(&rng, 8);
    ws_camera small = look_at(eye, target, 32, 32);
    for (int k = 0; k < 5000; k++) {
        mu5[3 * k] = 0.5 * 4 / small.focal + 1e-3 * ws_rng_normal(&rng);
        mu5[3 * k + 1] = -0.5 * 4 / small.focal + 1e-3 * ws_rng_normal(&rng);
        mu5[3 * k + 2] = 1e-3 * ws_rng_normal(&rng);
    }
    opt.cutoff = 4;
    ws_splat *s2;
    ws_splat_create(&s2, 32, 32, &st);
    CHECK(ws_splat_forward(s2, &small, mu5, 5000, radius, &opt, a, &st) == WS_OK, "5000 on a pixel");
    direct_alpha(&small, mu5, 5000, radius, 4, ref);
    CHECK(max_abs_diff(a, ref, 32 * 32) < 1e-12, "5000 on a pixel: matches the direct sum");
    CHECK(a[16 * 32 + 16] == 1.0, "5000 on a pixel: alpha 1 at the centre");
    CHECK(ws_splat_backward(s2, ones, dmu, &st) == WS_OK && all_finite(dmu, 3 * 5000),
          "5000 on a pixel: finite gradient");
    int some[3] = {0, 1234, 4999};
    opt.cutoff = INFINITY;
    /* L sums ~1000 alphas near 1, so its rounding (~1e-13) needs a step well
     * above 1e-7 world units; 1e-5 is still 1e-4 of the footprint. */
    check_dmu_fd("5000 on a pixel", &small, mu5, 5000, radius, &opt, some, 3, 1e-5, 1e-4);
    free(mu5);

    /* Off the image by 30 and 40 sigmas (sigma 1 px): alpha cannot show
     * w = exp(-450) next to 1, but the exact gradient does; at 40 sigmas
     * exp(-800) is 0 in double and so is the gradient. */
    double off[6] = {-62 * 4 / f, 0, 0, -72 * 4 / f, 0, 0};
    opt.cutoff = INFINITY;
    ws_splat_forward(s, &cam, off, 2, 4 / f, &opt, a, &st);
    ws_splat_backward(s, ones, dmu, &st);
    CHECK(dmu[0] != 0 && all_finite(dmu, 6), "30 sigmas off the image: exact gradient %g", dmu[0]);
    CHECK(dmu[3] == 0 && dmu[4] == 0 && dmu[5] == 0, "40 sigmas off the image: gradient 0");

    /* Nothing to draw. */
    CHECK(ws_splat_forward(s, &cam, NULL, 0, radius, &opt, a, &st) == WS_OK, "no Gaussians");
    double amax = 0;
    for (int p = 0; p < 64 * 64; p++) amax = fmax(amax, a[p]);
    CHECK(amax == 0, "no Gaussians: blank image");
    CHECK(ws_splat_backward(s, ones, dmu, &st) == WS_OK, "no Gaussians: backward");
    ws_splat_free(s);
    ws_splat_free(s2);
}

/* The far limit (hidden-line removal): of two Gaussians on one pixel's
 * centre, the one beyond the pixel's limit draws nothing and gets zero
 * gradient, the one in front draws what it draws alone; a centre outside
 * the image is not culled by it; NULL is see-through. */
static void test_far_limit(void) {
    ws_status st;
    const double eye[3] = {0, 0, 4}, target[3] = {0, 0, 0};
    ws_camera cam = look_at(eye, target, 64, 64);
    double f = cam.focal;
    /* both on the centre of pixel (32, 32): in front at depth 3.5, behind at 4.5 */
    double two[6] = {0.5 * 3.5 / f, -0.5 * 3.5 / f, 0.5, 0.5 * 4.5 / f, -0.5 * 4.5 / f, -0.5};
    double radius = 2 * 4 / f, front[64 * 64], a[64 * 64], ones[64 * 64], dmu[6];
    static float far[64 * 64];
    for (int p = 0; p < 64 * 64; p++) far[p] = p == 32 * 64 + 32 ? 4.0f : 0.0f;
    for (int p = 0; p < 64 * 64; p++) ones[p] = 1.0;
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    ws_splat *s;
    ws_splat_create(&s, 64, 64, &st);
    ws_splat_forward(s, &cam, two, 1, radius, &opt, front, &st);
    opt.far = far;
    CHECK(ws_splat_forward(s, &cam, two, 2, radius, &opt, a, &st) == WS_OK && !memcmp(a, front, sizeof a),
          "far limit: the Gaussian beyond it changed alpha");
    CHECK(ws_splat_backward(s, ones, dmu, &st) == WS_OK && dmu[3] == 0 && dmu[4] == 0 && dmu[5] == 0 &&
              (dmu[0] != 0 || dmu[1] != 0 || dmu[2] != 0),
          "far limit: gradients %g %g %g (in front), %g %g %g (beyond: 0)", dmu[0], dmu[1], dmu[2], dmu[3], dmu[4],
          dmu[5]);
    double ink = 0;
    for (int p = 0; p < 64 * 64; p++) ink += front[p];
    CHECK(ink > 1, "far limit: the Gaussian in front drew %g", ink);
    /* 1.5 px left of the image (limit 0 everywhere in it): its footprint reaches in */
    double outside[3] = {-33.5 * 4 / f, 0, 0};
    CHECK(ws_splat_forward(s, &cam, outside, 1, radius, &opt, a, &st) == WS_OK && a[32 * 64] > 0,
          "far limit: a centre outside the image was culled (alpha %g at its edge)", a[32 * 64]);
    opt.far = NULL;
    ws_splat_forward(s, &cam, two, 2, radius, &opt, a, &st);
    double both = 0;
    for (int p = 0; p < 64 * 64; p++) both += a[p];
    CHECK(both > ink, "no far limit: the Gaussian behind adds nothing (%g against %g)", both, ink);
    ws_splat_free(s);
}

/* Same input, same bits: twice with 2 threads and once with 1. */
static void test_determinism(void) {
    ws_status st;
    ws_rng rng;
    ws_rng_seed(&rng, 6);
    const double eye[3] = {2, 2, 2}, target[3] = {0, 0, 0};
    ws_camera cam = look_at(eye, target, 96, 80);
    int n = 4000, P = 96 * 80;
    double *mu = malloc(sizeof(double) * 3 * n), *dalpha = malloc(sizeof(double) * P);
    random_mu(&rng, mu, n, 0.5);
    for (int p = 0; p < P; p++) dalpha[p] = ws_rng_normal(&rng);
    double *alpha[3], *dmu[3];
    int threads[3] = {2, 2, 1};
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    for (int r = 0; r < 3; r++) {
        omp_set_num_threads(threads[r]);
        ws_splat *s;
        ws_splat_create(&s, 96, 80, &st);
        alpha[r] = malloc(sizeof(double) * P);
        dmu[r] = malloc(sizeof(double) * 3 * n);
        ws_splat_forward(s, &cam, mu, n, 0.02, &opt, alpha[r], &st);
        ws_splat_backward(s, dalpha, dmu[r], &st);
        ws_splat_free(s);
    }
    omp_set_num_threads(2);
    CHECK(!memcmp(alpha[0], alpha[1], sizeof(double) * P) && !memcmp(dmu[0], dmu[1], sizeof(double) * 3 * n),
          "two runs with 2 threads: identical bits");
    CHECK(!memcmp(alpha[0], alpha[2], sizeof(double) * P) && !memcmp(dmu[0], dmu[2], sizeof(double) * 3 * n),
          "1 thread and 2 threads: identical bits");

    /* A reused workspace (n shrinking and growing) gives the same answer. */
    ws_splat *s;
    ws_splat_create(&s, 96, 80, &st);
    double *a = malloc(sizeof(double) * P), *d = malloc(sizeof(double) * 3 * n);
    ws_splat_forward(s, &cam, mu, 10, 0.02, &opt, a, &st);
    ws_splat_forward(s, &cam, mu, n, 0.02, &opt, a, &st);
    ws_splat_backward(s, dalpha, d, &st);
    CHECK(!memcmp(a, alpha[0], sizeof(double) * P) && !memcmp(d, dmu[0], sizeof(double) * 3 * n),
          "reused workspace: identical bits");
    for (int r = 0; r < 3; r++) {
        free(alpha[r]);
        free(dmu[r]);
    }

    /* Errors. */
    ws_camera other = look_at(eye, target, 64, 64);
    CHECK(ws_splat_forward(s, &other, mu, n, 0.02, &opt, a, &st) == WS_EINTERNAL &&
              !strcmp(st.msg, "splat: camera is 64 x 64 but the workspace 96 x 80"),
          "size mismatch: %s", st.msg);
    CHECK(ws_splat_backward(s, dalpha, d, &st) == WS_EINTERNAL &&
              !strcmp(st.msg, "splat: backward without a forward pass"),
          "backward after a failed forward: %s", st.msg);
    mu[3 * 7 + 1] = NAN;
    CHECK(ws_splat_forward(s, &cam, mu, n, 0.02, &opt, a, &st) == WS_ENUMERIC &&
              !strcmp(st.msg, "splat: Gaussian 7 has a non-finite centre"),
          "NaN centre: %s", st.msg);
    mu[3 * 7 + 1] = 0;
    ws_splat_forward(s, &cam, mu, n, 0.02, &opt, a, &st);
    dalpha[5 * 96 + 3] = INFINITY;
    CHECK(ws_splat_backward(s, dalpha, d, &st) == WS_ENUMERIC &&
              !strcmp(st.msg, "splat: dL/dalpha is not finite at pixel (5, 3)"),
          "Inf dalpha: %s", st.msg);
    ws_splat *bad;
    CHECK(ws_splat_create(&bad, 0, 10, &st) == WS_EINPUT && bad == NULL, "size 0 refused");
    ws_splat_free(s);
    free(a);
    free(d);
    free(mu);
    free(dalpha);
}

int main(void) {
    omp_set_num_threads(2);
    test_fixture();
    test_forward_direct();
    test_gradients();
    test_end_to_end();
    test_stiff();
    test_far_limit();
    test_determinism();
    return check_summary();
}
