/* test_silhouette_loss.c: the silhouette-consistency term
 * (objective/silhouette_loss.h). On a synthetic trefoil (64 px, 26
 * training views, so parts of 9, 9 and 8 views): the ground-truth curve's
 * points pay nothing in any part (they lie inside every silhouette);
 * points off the object, some beyond a view's frame, pay, and the gradient
 * with respect to every centre coordinate agrees with central differences
 * in double; part p + M is part p, part p + 1 another; the term is the
 * same bits on 1 and 2 threads; ws_objective_batch adds exactly the weight
 * times the term of its first view's part and its gradient through the
 * Bernstein weights. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "scene_load.h"
#include "test_util.h"
#include "wiresketch.h"
#include "objective/silhouette_loss.h"
#include "objective/view_targets.h"
#include "synth/synth.h"

#define N_OFF 24

/* Points around the object: from its centre out to 3 times its size, so
 * that some project beyond a view's frame. */
static void off_points(const ws_scene *scene, double *mu, int n) {
    ws_rng rng;
    ws_rng_seed(&rng, 3);
    for (int g = 0; g < n; g++)
        for (int a = 0; a < 3; a++) mu[3 * g + a] = scene->center[a] + 3.0 * (ws_rng_uniform(&rng) - 0.5) * (1 + g % 3);
}

static void test_gradient(ws_silhouette_loss *term, const double *mu0, int n) {
    ws_status st = {0};
    double *mu = malloc(3 * n * sizeof(double)), *dmu = malloc(3 * n * sizeof(double));
    memcpy(mu, mu0, 3 * n * sizeof(double));
    double base;
    CHECK(ws_silhouette_loss_forward(term, mu, n, 1, &base, &st) == WS_OK, "forward: %s", st.msg);
    CHECK(base > 0.1, "points off the object pay %g", base);
    ws_silhouette_loss_backward(term, 2.0, dmu);
    double worst = 0, gmax = 0;
    int nonzero = 0;
    for (int i = 0; i < 3 * n; i++) {
        gmax = fmax(gmax, fabs(dmu[i]));
        nonzero += dmu[i] != 0;
    }
    for (int i = 0; i < 3 * n; i++) {
        double keep = mu[i], h = 1e-7, up, down;
        mu[i] = keep + h;
        ws_silhouette_loss_forward(term, mu, n, 1, &up, &st);
        mu[i] = keep - h;
        ws_silhouette_loss_forward(term, mu, n, 1, &down, &st);
        mu[i] = keep;
        worst = fmax(worst, fabs(2.0 * (up - down) / (2 * h) - dmu[i]) / gmax);
    }
    CHECK(nonzero > n && worst < 1e-5, "dS/dmu: %d non-zero entries, finite differences off by %.3g of the largest",
          nonzero, worst);
    printf("silhouette term %.6g over %d points: %d of %d gradient entries non-zero, worst error %.2g of max %.3g\n",
           base, n, nonzero, 3 * n, worst, gmax);
    free(mu);
    free(dmu);
}

/* ws_objective_batch with the term minus without: the weight times the
 * term, and the gradient through the curves' Gaussians. */
static void test_objective(const ws_scene *scene, ws_silhouette_loss *term) {
    ws_status st = {0};
    ws_curves c = {0};
    ws_rng rng;
    ws_rng_seed(&rng, 11);
    if (ws_curves_init_random(&c, 4, scene->center, 1.2, 0.5, 0.05, 0.6, &rng, &st)) {
        CHECK(0, "curves: %s", st.msg);
        return;
    }
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    lo.conv_weight = lo.fc_weight = lo.global_weight = 0;
    lo.lines_weight = 1;
    ws_splat_options so;
    ws_splat_options_default(&so);
    ws_objective *with = NULL, *without = NULL;
    int np = c.n * WS_CURVE_FLOATS, views[2] = {5, 1};
    double *g1 = malloc(np * sizeof(double)), *g0 = malloc(np * sizeof(double)), l1, l0, s;
    int rc = ws_objective_create(&without, scene, &lo, &so, c.n, &st);
    lo.silhouette_weight = 0.75;
    if (!rc) rc = ws_objective_create(&with, scene, &lo, &so, c.n, &st);
    ws_rng r1, r0;
    ws_rng_seed(&r1, 1);
    ws_rng_seed(&r0, 1);
    if (!rc) rc = ws_objective_batch(with, &c, views, 2, &r1, &l1, g1, &st);
    if (!rc) rc = ws_objective_batch(without, &c, views, 2, &r0, &l0, g0, &st);
    const ws_gaussians *g = ws_objective_gaussians(with);
    double *dmu = malloc(3 * (size_t)g->n * sizeof(double)), *dP = malloc(np * sizeof(double));
    if (!rc) rc = ws_silhouette_loss_forward(term, g->mu, g->n, views[0], &s, &st);
    CHECK(rc == WS_OK, "objective: %s", st.msg);
    if (!rc) {
        ws_silhouette_loss_backward(term, 0.75, dmu);
        ws_curves_backward(&c, g, dmu, dP);
        double worst = 0, gmax = 0;
        for (int i = 0; i < np; i++) {
            gmax = fmax(gmax, fabs(dP[i]));
            worst = fmax(worst, fabs((g1[i] - g0[i]) - dP[i]));
        }
        CHECK(s > 0 && check_close(l1 - l0, 0.75 * s, 1e-9, 1e-12), "batch loss %.17g - %.17g, 0.75 S = %.17g", l1,
              l0, 0.75 * s);
        CHECK(gmax > 0 && worst <= 1e-9 * gmax, "batch gradient off the term's by %.3g (max %.3g)", worst, gmax);
    }
    free(g1);
    free(g0);
    free(dmu);
    free(dP);
    ws_objective_free(with);
    ws_objective_free(without);
    ws_curves_free(&c);
}

int main(void) {
    const char *dir = test_tmpdir("silhouette_loss");
    char scene_dir[300];
    snprintf(scene_dir, sizeof scene_dir, "%s/scene", dir);
    ws_status st = {0};
    ws_synth_options syn;
    synth_options_at(&syn, 64, 26, 0, 1);
    ws_scene scene;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 64;
    ws_curves gt = {0};
    ws_gaussians on = {0};
    ws_silhouette_loss *term = NULL;
    ws_view_targets *targets = NULL;
    const ws_silhouette *sil;
    char path[400];
    snprintf(path, sizeof path, "%s/gt_curves.json", scene_dir);
    int rc = ws_runtime_init(1, &st);
    if (!rc) rc = ws_synth_write("trefoil", scene_dir, &syn, &st);
    if (!rc) rc = ws_scene_load(&scene, scene_dir, &so, &st);
    if (!rc) rc = ws_view_targets_create(&targets, &scene, &st);
    if (!rc) rc = ws_view_targets_silhouettes(targets, WS_TRAIN, &sil, &st);
    if (!rc) rc = ws_silhouette_loss_create(&term, &scene.split[WS_TRAIN], sil, &st);
    if (!rc) rc = ws_curves_load(path, &gt, &st);
    if (!rc) rc = ws_curves_sample(&gt, &on, &st);
    CHECK(rc == WS_OK, "setup: %s", st.msg);
    if (rc) return check_summary();

    CHECK(ws_silhouette_loss_stride(26) == 3 && ws_silhouette_loss_stride(96) == 8 &&
              ws_silhouette_loss_stride(12) == 1 && ws_silhouette_loss_stride(0) == 1,
          "parts of 26, 96, 12, 0 views: %d %d %d %d", ws_silhouette_loss_stride(26), ws_silhouette_loss_stride(96),
          ws_silhouette_loss_stride(12), ws_silhouette_loss_stride(0));
    for (int part = 0; part < 3; part++) {
        double s_on = -1;
        CHECK(ws_silhouette_loss_forward(term, on.mu, on.n, part, &s_on, &st) == WS_OK && s_on == 0,
              "the ground truth's %d Gaussians pay %g in part %d", on.n, s_on, part);
    }
    double none = -1;
    CHECK(ws_silhouette_loss_forward(term, NULL, 0, 0, &none, &st) == WS_OK && none == 0, "no Gaussians pay %g", none);

    double mu[3 * N_OFF];
    off_points(&scene, mu, N_OFF);
    test_gradient(term, mu, N_OFF);

    /* parts repeat every M = 3; the same bits on 2 threads */
    double one, two, p0, p3;
    ws_silhouette_loss_forward(term, mu, N_OFF, 0, &p0, &st);
    ws_silhouette_loss_forward(term, mu, N_OFF, 3, &p3, &st);
    ws_silhouette_loss_forward(term, mu, N_OFF, 1, &one, &st);
    CHECK(p0 == p3 && p0 != one, "parts 0, 3, 1: %.17g %.17g %.17g", p0, p3, one);
    CHECK(ws_runtime_init(2, &st) == WS_OK, "2 threads: %s", st.msg);
    ws_silhouette_loss_forward(term, mu, N_OFF, 1, &two, &st);
    CHECK(one == two, "1 thread %.17g, 2 threads %.17g", one, two);

    test_objective(&scene, term);

    ws_silhouette_loss_free(term);
    ws_view_targets_free(targets);
    ws_gaussians_free(&on);
    ws_curves_free(&gt);
    ws_scene_free(&scene);
    return check_summary();
}
