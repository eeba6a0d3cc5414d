/* test_respawn.c: idle curves go to the photos' uncovered edges
 * (fit/respawn.h). On a 128 px cube made by the program (32 training
 * views), the sketch is the cube's 12 edges less one, plus a dot
 * (collapsed: it has a gradient and lies inside every silhouette, so only
 * its size marks it idle), a hairpin (a curve whose ends met) and a stroke
 * across a face (no edge under it). One respawn step must move exactly
 * these three, one of them onto the missing edge (its middle within 2% of
 * the side, along it), and leave the others and their moments alone; the
 * same step on the same input gives the same bits; and the end of a fit
 * would retire these three alone. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_util.h"
#include "fit/respawn.h"
#include "scene_load.h"
#include "synth/synth.h"

/* The distance from p to curve ci of c, and the curve's unit direction at
 * its nearest sample (a straight ground-truth edge: end minus start). */
static double distance_to(const ws_curves *c, int ci, const double p[3]) {
    double best = INFINITY;
    for (int k = 0; k <= 400; k++) {
        double q[3];
        ws_curve_point(c, ci, k / 400.0, q);
        best = fmin(best, sqrt(pow(q[0] - p[0], 2) + pow(q[1] - p[1], 2) + pow(q[2] - p[2], 2)));
    }
    return best;
}

static void direction(const ws_curves *c, int ci, double d[3]) {
    const double *P = c->P + (size_t)ci * WS_CURVE_FLOATS;
    double n = 0;
    for (int a = 0; a < 3; a++) {
        d[a] = P[9 + a] - P[a];
        n += d[a] * d[a];
    }
    for (int a = 0; a < 3; a++) d[a] /= sqrt(n);
}

static int make_sketch(const ws_curves *gt, ws_curves *sk, ws_status *st) {
    if (ws_curves_alloc(sk, gt->n + 2, st)) return st->code; /* 11 edges, a dot, a hairpin, a face stroke */
    sk->thickness = 0.01;
    sk->overlap = 0.6;
    /* curves 0..10: the truth's edges 1..11; 11: a dot at the middle of
     * edge 1; 12: the hairpin; 13: the face stroke */
    memcpy(sk->P, gt->P + WS_CURVE_FLOATS, sizeof(double) * WS_CURVE_FLOATS * (gt->n - 1));
    double mid[3];
    ws_curve_point(gt, 1, 0.5, mid);
    for (int j = 0; j < 4; j++) memcpy(sk->P + (size_t)(gt->n - 1) * WS_CURVE_FLOATS + 3 * j, mid, sizeof mid);
    /* the hairpin: both ends at edge 2's middle, the bend 0.01 away */
    double *h = sk->P + (size_t)gt->n * WS_CURVE_FLOATS, m2[3];
    ws_curve_point(gt, 2, 0.5, m2);
    for (int j = 0; j < 4; j++)
        for (int a = 0; a < 3; a++) h[3 * j + a] = m2[a] + (a == 0 && (j == 1 || j == 2) ? 0.013 : 0.0);
    /* across the middle of the face y = -0.75, away from its edges */
    double *f = h + WS_CURVE_FLOATS;
    for (int j = 0; j < 4; j++) {
        f[3 * j] = 0.1 + 0.1 * j;
        f[3 * j + 1] = -0.75;
        f[3 * j + 2] = 0.35 + 0.1 * j;
    }
    return WS_OK;
}

int main(void) {
    const char *tmp = test_tmpdir("respawn");
    char dir[300], path[400];
    ws_status st;
    ws_synth_options syn;
    synth_options_at(&syn, 128, 32, 0, 0);
    snprintf(dir, sizeof dir, "%s/cube", tmp);
    CHECK(ws_synth_write("cube", dir, &syn, &st) == WS_OK, "scene: %s", st.msg);
    ws_scene scene;
    CHECK(load_scene_at(&scene, dir, 128, &st) == WS_OK, "load: %s", st.msg);
    ws_curves gt, sk, again;
    snprintf(path, sizeof path, "%s/gt_curves.json", dir);
    CHECK(ws_curves_load(path, &gt, &st) == WS_OK && gt.n == 12, "ground truth: %s", st.msg);
    make_sketch(&gt, &sk, &st);
    make_sketch(&gt, &again, &st);
    ws_respawn *r;
    ws_view_targets *targets;
    ws_scene_hull hull;
    const ws_silhouette *sil;
    CHECK(ws_view_targets_create(&targets, &scene, &st) == WS_OK &&
              ws_view_targets_silhouettes(targets, WS_TRAIN, &sil, &st) == WS_OK &&
              ws_scene_hull_make(&scene, WS_TRAIN, sil, WS_HULL_INIT_RESOLUTION, &hull, &st) == WS_OK &&
              ws_respawn_create(&r, &scene, targets, &hull, sk.n, 0.3, &st) == WS_OK,
          "respawn: %s", st.msg);
    int retire[14];
    CHECK(ws_respawn_retire(r, &sk, retire, &st) == WS_OK, "retire: %s", st.msg);
    int marked = 0;
    for (int ci = 0; ci < sk.n; ci++) marked += retire[ci] << ci;
    CHECK(marked == (1 << 11 | 1 << 12 | 1 << 13),
          "retired curves %#x, want the dot, the hairpin and the face stroke (0x3800)", marked);
    ws_adam adam, adam2;
    ws_adam_init(&adam, sk.n * WS_CURVE_FLOATS, 1e-3, &st);
    ws_adam_init(&adam2, sk.n * WS_CURVE_FLOATS, 1e-3, &st);
    for (int i = 0; i < adam.n; i++) adam.v[i] = adam2.v[i] = 1; /* every curve had a gradient */
    int moved = 0, moved2 = 0;
    CHECK(ws_respawn_step(r, &sk, &adam, &moved, &st) == WS_OK, "step: %s", st.msg);
    CHECK(moved == 3, "%d curves moved, want 3 (the dot, the hairpin, the face stroke)", moved);
    CHECK(!memcmp(sk.P, gt.P + WS_CURVE_FLOATS, sizeof(double) * WS_CURVE_FLOATS * 11),
          "a curve on an edge was moved");
    CHECK(adam.v[11 * WS_CURVE_FLOATS] == 0 && adam.v[13 * WS_CURVE_FLOATS] == 0 && adam.v[0] == 1,
          "the moved curves' moments are reset, the others kept");
    /* one of the two now lies on the missing edge 0, along it */
    double side = 1.1, best = INFINITY, cosine = 0;
    for (int ci = 11; ci < 14; ci++) {
        double mid[3], d[3], e[3];
        ws_curve_point(&sk, ci, 0.5, mid);
        double dist = distance_to(&gt, 0, mid);
        if (dist >= best) continue;
        best = dist;
        direction(&sk, ci, d);
        direction(&gt, 0, e);
        cosine = fabs(d[0] * e[0] + d[1] * e[1] + d[2] * e[2]);
    }
    CHECK(best < 0.02 * side, "no respawned curve on the missing edge (nearest %.4f of %.2f)", best, side);
    CHECK(cosine > 0.95, "the stroke on the missing edge is not along it (|cos| %.3f)", cosine);
    CHECK(ws_respawn_step(r, &again, &adam2, &moved2, &st) == WS_OK && moved2 == moved &&
              !memcmp(sk.P, again.P, sizeof(double) * WS_CURVE_FLOATS * sk.n),
          "the same step on the same input differs");
    ws_respawn_free(r);
    ws_view_targets_free(targets);
    ws_scene_hull_free(&hull);
    ws_adam_free(&adam);
    ws_adam_free(&adam2);
    ws_curves_free(&sk);
    ws_curves_free(&again);
    ws_curves_free(&gt);
    ws_scene_free(&scene);
    return check_summary();
}
