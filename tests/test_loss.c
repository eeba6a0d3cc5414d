/* test_loss.c: the whole loss of METHOD.md section 6, end to end: control points
 * -> Gaussians -> splatting -> augmentation -> CLIP (the tiny fixture model,
 * converted by tools/convert_weights.py) -> geometric, fc and global terms,
 * and back. The gradient with respect to the control points is checked
 * against central finite differences, with augmentation off and on (the same
 * transforms for both sides of a difference: the rng is restored), and with
 * the edge loss added, and with the geometric term's attention-map variant
 * (alone, the CLIP backward starts at the attention probabilities: no
 * block output gets a gradient). A view's loss computed in parts (its CLIP
 * passes on separate loss objects, as MPI ranks do, in another order) must
 * be the bits of the whole, in both variants; the pass size changes only
 * the rounding. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "scene_load.h"
#include "test_util.h"
#include "wiresketch.h"
#include "objective/hidden_lines.h"
#include "synth/synth.h"

typedef struct {
    ws_scene scene;
    ws_loss *loss;
    ws_splat *splat;
    ws_splat_options so;
    ws_hidden_lines *hidden; /* NULL: every Gaussian drawn */
    int n_hidden;            /* Gaussians of the last gradient that got none (culled) */
    ws_gaussians g;
    double *alpha, *dalpha, *dmu;
} setup;

/* The loss of view 0 of the training split for curves c; with dP, its
 * gradient. rng0: the augmentation stream, restored for every evaluation.
 * With dP the curves are sampled anew; without, the Gaussians keep the
 * parameters t_k of the last sampling (METHOD.md section 2: the t_k are constants of the
 * backward pass, so the finite differences must hold them too). With hidden
 * lines removed, the view's far limit culls the Gaussians behind it. */
static double loss_of(setup *s, const ws_curves *c, int augment, const ws_rng *rng0, double *dP) {
    ws_status st = {0};
    ws_rng rng = *rng0;
    double value = NAN;
    if (dP && ws_curves_sample(c, &s->g, &st)) return NAN;
    for (int k = 0; !dP && k < s->g.n; k++) ws_curve_point(c, s->g.curve[k], s->g.t[k], s->g.mu + 3 * k);
    if (s->hidden && ws_hidden_lines_far(s->hidden, WS_TRAIN, 0, &s->so.far, &st)) return NAN;
    if (ws_splat_forward(s->splat, &s->scene.split[WS_TRAIN].views[0].cam, s->g.mu, s->g.n, c->thickness,
                         &s->so, s->alpha, &st) ||
        ws_loss_view(s->loss, WS_TRAIN, 0, s->alpha, augment, &rng, &value, dP ? s->dalpha : NULL, &st)) {
        fprintf(stderr, "loss: %s\n", st.msg);
        return NAN;
    }
    if (dP) {
        if (ws_splat_backward(s->splat, s->dalpha, s->dmu, &st)) return NAN;
        ws_curves_backward(c, &s->g, s->dmu, dP);
        /* at the exact sum every drawn Gaussian reaches every pixel: only a culled one gets 0 */
        s->n_hidden = 0;
        for (int k = 0; k < s->g.n; k++)
            s->n_hidden += s->dmu[3 * k] == 0 && s->dmu[3 * k + 1] == 0 && s->dmu[3 * k + 2] == 0;
    }
    return value;
}

/* Curves crossing the object, long enough to cover many pixels. */
static void make_curves(ws_curves *c, const double center[3], ws_rng *rng) {
    for (int k = 0; k < c->n; k++)
        for (int j = 0; j < 4; j++)
            for (int x = 0; x < 3; x++)
                c->P[(k * 4 + j) * 3 + x] = center[x] + 0.6 * (ws_rng_uniform(rng) - 0.5) + 0.15 * j;
}

static void check_gradient(setup *s, ws_curves *c, int augment, const char *what) {
    ws_rng rng0;
    ws_rng_seed(&rng0, 99);
    int np = c->n * WS_CURVE_FLOATS;
    double *dP = malloc(np * sizeof(double));
    double base = loss_of(s, c, augment, &rng0, dP);
    CHECK(isfinite(base) && base > 0, "%s: loss %g", what, base);
    /* the largest gradient entries: there float32 CLIP's rounding is
     * small against the change a step of h makes */
    double worst = 0, gmax = 0;
    for (int i = 0; i < np; i++) gmax = fmax(gmax, fabs(dP[i]));
    int checked = 0;
    for (int i = 0; i < np && checked < 6; i++) {
        if (fabs(dP[i]) < 0.3 * gmax) continue;
        double keep = c->P[i], h = 2e-4;
        c->P[i] = keep + h;
        double up = loss_of(s, c, augment, &rng0, NULL);
        c->P[i] = keep - h;
        double down = loss_of(s, c, augment, &rng0, NULL);
        c->P[i] = keep;
        double fd = (up - down) / (2 * h);
        worst = fmax(worst, fabs(fd - dP[i]) / gmax);
        checked++;
    }
    CHECK(checked >= 3 && worst < 5e-3, "%s: finite differences off by %.3g of the largest entry (%d checked)",
          what, worst, checked);
    printf("%-40s loss %.6g, %d entries, worst error %.2g of max |dL/dP| %.3g\n", what, base, checked, worst, gmax);
    free(dP);
}

static int make_setup(setup *s, const char *dir, const char *weights, const ws_loss_options *lo) {
    ws_status st = {0};
    int rc = load_scene_at(&s->scene, dir, 64, &st);
    if (!rc) rc = ws_loss_create(&s->loss, lo, &s->scene, &st);
    if (!rc) rc = ws_splat_create(&s->splat, 64, 64, &st);
    CHECK(rc == WS_OK, "setup: %s", st.msg);
    ws_splat_options_default(&s->so);
    s->so.cutoff = INFINITY; /* a cut-off is a kink for finite differences */
    s->alpha = malloc(64 * 64 * sizeof(double));
    s->dalpha = malloc(64 * 64 * sizeof(double));
    s->dmu = malloc(4 * WS_MAX_GAUSSIANS_PER_CURVE * 3 * sizeof(double));
    (void)weights;
    return rc;
}

static void free_setup(setup *s) {
    ws_loss_free(s->loss);
    ws_hidden_lines_free(s->hidden);
    ws_splat_free(s->splat);
    ws_gaussians_free(&s->g);
    ws_scene_free(&s->scene);
    free(s->alpha);
    free(s->dalpha);
    free(s->dmu);
}

/* View 0's loss and dL/dalpha for the stroke image alpha with passes of G
 * items: whole (one object) and in parts (passes spread over two other
 * objects that drew the same transforms, last pass first). */
static void check_passes(const ws_scene *scene, ws_loss_options lo, int G, const double *alpha, double *whole) {
    ws_status st = {0};
    size_t pixels = 64 * 64;
    lo.pass_items = G;
    ws_loss *L[3] = {0};
    for (int k = 0; k < 3; k++)
        if (ws_loss_create(&L[k], &lo, scene, &st)) {
            CHECK(0, "G = %d: %s", G, st.msg);
            goto done;
        }
    int n = ws_loss_items(L[0], 1), P = ws_loss_passes(L[0], 1);
    CHECK(n == 1 + lo.num_aug && P == (n + G - 1) / G, "G = %d: %d items in %d passes", G, n, P);
    double *d_whole = malloc(pixels * sizeof(double)), *d_parts = malloc(pixels * sizeof(double));
    double item_loss[1 + WS_LOSS_MAX_AUG], parts = NAN;
    float *item_grad = malloc(n * pixels * sizeof(float));
    ws_rng r0, r1, r2;
    ws_rng_seed(&r0, 77);
    r1 = r2 = r0;
    int rc = ws_loss_view(L[0], WS_TRAIN, 0, alpha, 1, &r0, whole, d_whole, &st);
    rc = rc || ws_loss_draw(L[1], WS_TRAIN, 0, &r1, &st) || ws_loss_draw(L[2], WS_TRAIN, 0, &r2, &st);
    for (int p = P - 1; p >= 0 && !rc; p--) {
        int first, count;
        ws_loss_pass_items(L[0], 1, p, &first, &count);
        CHECK(first == p * G && count == (n - first < G ? n - first : G), "G = %d: pass %d holds items %d + %d", G,
              p, first, count);
        rc = ws_loss_pass(L[1 + p % 2], WS_TRAIN, 0, alpha, 1, p, item_loss + first, item_grad + first * pixels, &st);
    }
    rc = rc || ws_loss_combine(L[2], WS_TRAIN, 0, alpha, 1, item_loss, item_grad, &parts, d_parts, &st);
    CHECK(rc == WS_OK, "G = %d: %s", G, st.msg);
    CHECK(!rc && parts == *whole && !memcmp(d_whole, d_parts, pixels * sizeof(double)),
          "G = %d: the view in parts gives loss %.17g, whole %.17g (or another dL/dalpha)", G, parts, *whole);
    free(d_whole);
    free(d_parts);
    free(item_grad);
done:
    for (int k = 0; k < 3; k++) ws_loss_free(L[k]);
}

static void test_passes(const char *scene_dir, const ws_loss_options *lo) {
    ws_status st = {0};
    ws_scene scene = {0};
    if (load_scene_at(&scene, scene_dir, 64, &st)) {
        CHECK(0, "%s", st.msg);
        return;
    }
    double alpha[64 * 64], loss[4];
    for (int i = 0; i < 64 * 64; i++) alpha[i] = (i % 64 > 20 && i % 64 < 30) || (i / 64 > 40 && i / 64 < 44);
    for (int G = 1; G <= 3; G++) check_passes(&scene, *lo, G, alpha, &loss[G]);
    CHECK(fabs(loss[1] - loss[3]) < 1e-5 * fabs(loss[3]) && fabs(loss[2] - loss[3]) < 1e-5 * fabs(loss[3]),
          "passes of 1, 2, 3 items: losses %.9g %.9g %.9g", loss[1], loss[2], loss[3]);
    printf("%-40s loss %.9g (G = 1), %.9g (G = 2), %.9g (G = 3)\n", "a view in parts, passes of G items", loss[1],
           loss[2], loss[3]);
    ws_loss_options bad = *lo;
    bad.pass_items = 2 + lo->num_aug;
    ws_loss *L = NULL;
    CHECK(ws_loss_create(&L, &bad, &scene, &st) == WS_EUSAGE &&
              !strcmp(st.msg, "--clip-batch: 4 is not in 0..3 (1 + --num-aug)"),
          "pass size 4 of 3 items: '%s'", st.msg);
    ws_loss_free(L);
    ws_scene_free(&scene);
}

int main(void) {
    const char *dir = test_tmpdir("loss");
    char scene[300], weights[300], cmd[1024];
    snprintf(scene, sizeof scene, "%s/scene", dir);
    snprintf(weights, sizeof weights, "%s/tiny.bin", dir);
    snprintf(cmd, sizeof cmd, "python3 tools/convert_weights.py tests/fixtures/clip_tiny/clip_tiny_state_dict.pt %s >/dev/null",
             weights);
    CHECK(system(cmd) == 0, "converting the tiny model failed");
    ws_status st = {0};
    ws_synth_options syn;
    synth_options_at(&syn, 64, 2, 0, 1);
    CHECK(ws_synth_write("trefoil", scene, &syn, &st) == WS_OK, "scene: %s", st.msg);

    ws_loss_options lo;
    ws_loss_options_default(&lo);
    /* the line loss alone (no CLIP), in training at progress 0.3 (levels
     * 1..3 weighted 0.2, 1, 1) and in evaluation (all levels): double
     * precision end to end */
    lo.conv_weight = lo.fc_weight = lo.global_weight = 0;
    lo.lines_weight = 2;
    {
        setup s = {0};
        ws_curves c = {0};
        ws_rng rng;
        ws_rng_seed(&rng, 8);
        if (make_setup(&s, scene, NULL, &lo) == WS_OK && ws_curves_alloc(&c, 3, &st) == WS_OK) {
            c.thickness = 0.03;
            c.overlap = 0.6;
            make_curves(&c, s.scene.center, &rng);
            ws_loss_set_progress(s.loss, 0.3);
            check_gradient(&s, &c, 1, "lines, training at progress 0.3");
            check_gradient(&s, &c, 0, "lines, evaluation");
        }
        ws_curves_free(&c);
        free_setup(&s);
    }
    /* The same with hidden lines removed by the hull of a cube's 8 training
     * views: the far limit culls some Gaussians (those inside the cube), and
     * the gradient is that of the loss of those it lets through. */
    {
        setup s = {0};
        ws_curves c = {0};
        ws_rng rng;
        ws_rng_seed(&rng, 8);
        char cube[320];
        snprintf(cube, sizeof cube, "%s/cube", dir);
        syn.views[WS_TRAIN] = 8;
        CHECK(ws_synth_write("cube", cube, &syn, &st) == WS_OK, "cube: %s", st.msg);
        if (make_setup(&s, cube, NULL, &lo) == WS_OK && ws_curves_alloc(&c, 3, &st) == WS_OK &&
            ws_hidden_lines_create(&s.hidden, &s.scene, NULL, ws_loss_targets(s.loss), &st) == WS_OK) {
            c.thickness = 0.03;
            c.overlap = 0.6;
            make_curves(&c, s.scene.center, &rng);
            check_gradient(&s, &c, 0, "lines, hidden lines removed");
            CHECK(s.n_hidden > 0 && s.n_hidden < s.g.n, "hidden lines: %d of %d Gaussians hidden", s.n_hidden,
                  s.g.n);
            printf("hidden lines: %d of %d Gaussians hidden\n", s.n_hidden, s.g.n);
        }
        CHECK(s.hidden, "hidden lines: %s", st.msg);
        ws_curves_free(&c);
        free_setup(&s);
    }
    ws_loss_options_default(&lo);
    lo.weights_path = weights;
    lo.n_layer_weights = 2;
    lo.layer_weights[0] = 1;
    lo.layer_weights[1] = 1;
    lo.layer_weights[2] = lo.layer_weights[3] = 0;
    lo.num_aug = 2;
    setup s = {0};
    ws_curves c = {0};
    ws_rng rng;
    ws_rng_seed(&rng, 5);
    if (make_setup(&s, scene, weights, &lo) == WS_OK && ws_curves_alloc(&c, 3, &st) == WS_OK) {
        c.thickness = 0.04;
        c.overlap = 0.6;
        make_curves(&c, s.scene.center, &rng);
        check_gradient(&s, &c, 0, "CLIP, item 0 only");
        check_gradient(&s, &c, 1, "CLIP, 1 + 2 augmented items");
        /* Evaluation never draws from the rng; augmenting draws, and a
         * different stream gives a different loss. */
        ws_rng a, b;
        ws_rng_seed(&a, 1);
        ws_rng_seed(&b, 2);
        double la = loss_of(&s, &c, 1, &a, NULL), lb = loss_of(&s, &c, 1, &b, NULL);
        CHECK(isfinite(la) && isfinite(lb), "loss %g %g", la, lb);
        CHECK(la != lb, "augmentations do not change the loss (%g)", la);
        CHECK(loss_of(&s, &c, 1, &a, NULL) == la, "the same transforms give a different loss");
    }
    free_setup(&s);
    test_passes(scene, &lo);
    memset(&s, 0, sizeof s);
    lo.edges_weight = 0.5;
    lo.fc_weight = 0;
    if (make_setup(&s, scene, weights, &lo) == WS_OK && c.P) check_gradient(&s, &c, 1, "CLIP geometric + global + edges");
    free_setup(&s);
    /* The attention-map variant: alone, then with the fc and global terms. */
    ws_loss_options la = lo;
    la.geometric = WS_GEOMETRIC_ATTENTION;
    la.edges_weight = la.fc_weight = la.global_weight = 0;
    memset(&s, 0, sizeof s);
    if (make_setup(&s, scene, weights, &la) == WS_OK && c.P) {
        check_gradient(&s, &c, 0, "CLIP attention maps, item 0 only");
        check_gradient(&s, &c, 1, "CLIP attention, 1 + 2 augmented items");
    }
    free_setup(&s);
    la.fc_weight = 0.1;
    la.global_weight = 1;
    memset(&s, 0, sizeof s);
    if (make_setup(&s, scene, weights, &la) == WS_OK && c.P) check_gradient(&s, &c, 1, "CLIP attention maps + fc + global");
    free_setup(&s);
    test_passes(scene, &la);
    /* The scene's size must be the model's input size. */
    memset(&s, 0, sizeof s);
    ws_loss *loss = NULL;
    if (load_scene_at(&s.scene, scene, 48, &st) == WS_OK) {
        int rc = ws_loss_create(&loss, &lo, &s.scene, &st);
        CHECK(rc == WS_EUSAGE && strstr(st.msg, "tiny.bin: the model takes 64 x 64 images but the scene is loaded at 48 x 48"),
              "size mismatch: %s", st.msg);
    }
    ws_loss_free(loss);
    ws_loss_options bad = lo;
    bad.geometric = (ws_geometric)7;
    CHECK(ws_loss_options_check(&bad, &st) == WS_EUSAGE &&
              !strcmp(st.msg, "--clip-geometric: variant 7 is not blocks (0) or attention (1)"),
          "unknown geometric variant: '%s'", st.msg);
    ws_scene_free(&s.scene);
    ws_curves_free(&c);
    return check_summary();
}
