/* test_fit_time.c: the time left follows the schedule's phases
 * (fit_time.h). No clock is read: a test that times itself passes or fails
 * with the machine's load. Instead the estimator is fed a run whose costs
 * are known:
 *   - the phases of a 360-step edge-loss schedule (four, the line loss's
 *     levels), modelled at 1 : 1.7 : 2.6 : 3.9 (the model is what the
 *     timing before the first step measures);
 *   - each step's batch costs its phase's model times a factor the model
 *     does not know (0.9 - 1.15 per phase, as a short timing misses), times
 *     the machine's speed (2 wall seconds per modelled one), with noise
 *     (+-10%) and a view's first batch 4 times as long (its hidden-line
 *     map), plus a step's other work (Adam; a checkpoint every 50 steps);
 *   - at every step past the first 10% of the run, the time left it tells
 *     must be within 25% of what the remaining steps cost, and the same
 *     estimator with every phase modelled alike (the former extrapolation
 *     of the current rate) must miss by more, or the run shows nothing of
 *     the phases.
 * The measured accuracy on real fits is a benchmark's (docs/RESULTS.md);
 * here a real fit only shows that it prints the phases it is estimated by.
 * And the estimate before the first step, with its warning past an hour. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_util.h"
#include "fit/fit_time.h"

static const char *bin, *tmp;

enum { STEPS = 360, WARMUP = 10 };

/* A deterministic noise in [-1, 1). */
static double noise(unsigned *state) {
    *state = *state * 1664525u + 1013904223u;
    return (*state >> 8) / (double)(1u << 23) - 1;
}

/* The simulated run above; returns the worst |told - true| / true from 10%
 * of the run on, at step *at; flat: every phase modelled alike. */
static double worst_error(int flat, long *at) {
    static const double model[4] = {1e-3, 1.7e-3, 2.6e-3, 3.9e-3}, missed[4] = {0.9, 1.15, 1.0, 1.1};
    ws_fit_time t;
    ws_status st;
    CHECK(ws_fit_time_phases(&t, STEPS, STEPS, 1, &st) == WS_OK, "phases: %s", st.msg);
    CHECK(t.n == 4, "an edge-loss schedule of %d steps has %d phases, not 4", STEPS, t.n);
    if (t.n != 4) return INFINITY;
    double batch[STEPS], besides[STEPS];
    unsigned state = 12345;
    for (long s = 0; s < STEPS; s++) {
        int k = 0;
        while (k + 1 < t.n && s >= t.first[k + 1]) k++;
        batch[s] = 2 * model[k] * missed[k] * (1 + 0.1 * noise(&state)) * (s % 48 < 4 && s < 48 ? 4 : 1);
        besides[s] = 2e-4 * (1 + 0.1 * noise(&state)) + (s % 50 == 49 ? 5e-3 : 0);
    }
    for (int k = 0; k < t.n; k++) t.model[k] = flat ? 2e-3 : model[k];
    t.wall_per_cpu = 2;
    double worst = 0;
    for (long s = 0; s < STEPS; s++) {
        if (s >= (STEPS + 9) / 10) {
            double truth = 0;
            for (long r = s; r < STEPS; r++) truth += batch[r] + besides[r];
            double e = fabs(ws_fit_time_left(&t, s) - truth) / truth;
            if (e > worst) worst = e, *at = s;
        }
        const double b[2] = {batch[s], batch[s] / 2}, all[2] = {batch[s] + besides[s], (batch[s] + besides[s]) / 2};
        ws_fit_time_add(&t, s, b, all);
    }
    ws_fit_time_free(&t);
    return worst;
}

static void test_time_left(void) {
    long at = 0, flat_at = 0;
    double e = worst_error(0, &at), flat = worst_error(1, &flat_at);
    printf("time left: worst error %.1f%% (step %ld), %.1f%% (step %ld) with every phase alike\n", 100 * e, at,
           100 * flat, flat_at);
    CHECK(e <= 0.25, "the time left is %.0f%% off at step %ld", 100 * e, at);
    CHECK(flat > 0.25, "every phase alike would do (%.0f%% off at most): the run shows nothing", 100 * flat);
}

/* The estimate before the first step, in words, and past an hour the
 * warning that names faster settings: a model of 2 phases of 0.5 s steps. */
static void test_announce(void) {
    ws_fit_time t;
    ws_status st;
    CHECK(ws_fit_time_phases(&t, 100000, 100000, 0, &st) == WS_OK, "phases: %s", st.msg);
    t.model[0] = 0.5;
    ws_fit_options opt;
    ws_fit_options_default(&opt);
    static char text[2048];
    FILE *f = fmemopen(text, sizeof text, "w");
    ws_fit_time_announce(&t, 99920, &opt, f); /* 80 steps: 40 s */
    ws_fit_time_announce(&t, 0, &opt, f);     /* 100000 steps: about 14 h */
    fclose(f);
    char want[1024];
    snprintf(want, sizeof want,
             "fit: 80 steps, about 40 s (1 phase of the schedule timed before the first step)\n"
             "fit: 100000 steps, about 14 h (1 phase of the schedule timed before the first step)\n"
             "wiresketch: warning: about 14 h on this machine; faster: --epochs (now %d), --inner-steps (now %d) or "
             "--max-steps N for fewer steps; --num-aug (now %d) for fewer images a step; --loss edges (no CLIP)\n",
             opt.epochs, opt.inner_steps, opt.loss.num_aug);
    CHECK(!strcmp(text, want), "the estimates: %s", text);
    ws_fit_time_free(&t);
}

int main(void) {
    test_announce();
    test_time_left();
    bin = program_path();
    tmp = test_tmpdir("fit_time");
    static char out[1 << 16];
    int rc = run_cmd(out, sizeof out,
                     "%s scene cube --out %s/cube --size 160 --views-train 6 --views-val 1 --views-test 1", bin, tmp);
    CHECK(rc == 0, "scene: %s", out);
    rc = run_cmd(out, sizeof out,
                 "%s fit %s/cube --out %s/fit --loss edges --size 160 --epochs 12 --inner-steps 5 --eval-every 0 "
                 "--threads 1 --n-curves 12",
                 bin, tmp, tmp);
    CHECK(rc == 0, "fit: %s", out);
    CHECK(strstr(out, "fit: 360 steps, about ") != NULL, "the estimate before the first step: %s", out);
    for (int k = 1; k <= 4; k++) {
        char want[64];
        snprintf(want, sizeof want, "fit: phase %d: steps ", k);
        CHECK(strstr(out, want) != NULL, "the fit's last words name phase %d: %s", k, out);
    }
    CHECK(strstr(out, "fit: phase 5:") == NULL, "four phases, not more: %s", out);
    return check_summary();
}
