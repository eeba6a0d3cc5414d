/* alone test */
/* test_fit_time.c: the time left follows the schedule's phases. A short
 * edge-loss fit of a synthetic cube (the line loss adds its finer levels
 * as it goes, so later steps cost more) prints every phase's modelled CPU
 * cost per step (timed before the first step) and its measured one. At
 * every step past the first 10% of the run, the time left the fit tells
 * (fit_time.h: the modelled costs of the remaining steps' batches, scaled
 * by the current phase's measured over modelled cost, plus what the steps
 * so far cost besides their batch) must be within 25% of the remaining
 * steps' measured cost. Both are CPU time (one thread), which
 * the machine's load leaves alone; the bound is on their ratio, the
 * remaining work in steps of the current phase. The same check with every
 * step costed alike (the former extrapolation of the current rate) must
 * fail it, or the scene shows nothing of the phases. And the estimate
 * before the first step, with its warning past an hour. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "fit/fit_time.h"

#define PHASES 8
static const char *bin, *tmp;

typedef struct {
    int n;
    long first[PHASES + 1];
    double model[PHASES], batch[PHASES], median[PHASES], besides[PHASES];
} phases;

static int parse(const char *out, phases *p) {
    p->n = 0;
    for (const char *at = strstr(out, "fit: phase "); at && p->n < PHASES; at = strstr(at + 1, "fit: phase ")) {
        int k;
        long a, b;
        double m, c, med, o;
        if (sscanf(at, "fit: phase %d: steps %ld-%ld, modelled %lf ms, measured %lf ms CPU per step in the batch "
                       "(median %lf) + %lf ms besides", &k, &a, &b, &m, &c, &med, &o) != 7 || k != p->n + 1)
            return 0;
        p->first[p->n] = a;
        p->first[p->n + 1] = b + 1;
        p->model[p->n] = m;
        p->batch[p->n] = c;
        p->median[p->n] = med;
        p->besides[p->n] = o;
        p->n++;
    }
    return p->n;
}

/* The worst |told - true| / true over the steps from 10% on; flat: every
 * step modelled alike. */
static double worst_error(const phases *p, int flat, long *at) {
    long total = p->first[p->n], from = (total + 9) / 10;
    double worst = 0;
    for (long s = from; s < total; s++) {
        int cur = 0;
        while (cur + 1 < p->n && s >= p->first[cur + 1]) cur++;
        /* the live model's scale: the median of the last steps' cost over
         * their model, here the median of the phase that most of them are in */
        int ref = cur;
        while (ref > 0 && s - p->first[ref] < 32) ref--;
        /* besides the batch: the mean over the phases up to here */
        double besides = 0;
        for (int k = 0; k <= cur; k++)
            besides += p->besides[k] * (double)((k == cur ? s : p->first[k + 1]) - p->first[k]);
        besides /= (double)s;
        double told = 0, truth = 0;
        for (int k = cur; k < p->n; k++) {
            long steps = p->first[k + 1] - (k == cur ? s : p->first[k]);
            double model = flat ? 1 : p->model[k], ref_model = flat ? 1 : p->model[ref];
            told += steps * (model / ref_model * p->median[ref] + besides);
            truth += steps * (p->batch[k] + p->besides[k]);
        }
        double e = fabs(told - truth) / truth;
        if (e > worst) {
            worst = e;
            *at = s;
        }
    }
    return worst;
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
    phases p;
    CHECK(parse(out, &p) == 4 && p.first[p.n] == 360, "four phases of 360 steps: %s", out);
    CHECK(strstr(out, "fit: 360 steps, about ") != NULL, "the estimate before the first step: %s", out);
    if (p.n == 4) {
        long at = 0, flat_at = 0;
        double e = worst_error(&p, 0, &at), flat = worst_error(&p, 1, &flat_at);
        printf("time left: worst error %.1f%% (step %ld), %.1f%% (step %ld) with every step alike\n", 100 * e, at,
               100 * flat, flat_at);
        CHECK(e <= 0.25, "the time left is %.0f%% off at step %ld: %s", 100 * e, at, out);
        CHECK(flat > 0.25, "every step alike would do (%.0f%% off at most): the test shows nothing", 100 * flat);
    }
    return check_summary();
}
