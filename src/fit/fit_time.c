/* fit_time.c: what a fit's schedule will take (see fit_time.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "base/distributed.h"
#include "base/sort.h"
#include "base/timing.h"
#include "fit/fit_time.h"
#include "objective/lines.h"

double ws_cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The median of v[0..n) (n > 0), which it reorders. */
static double median(double *v, size_t n) {
    ws_sort_doubles(v, n);
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

/* The line loss's levels in use at a step, as a bit set. */
static unsigned levels_at(long step, long schedule) {
    double w[WS_LINES_LEVELS];
    ws_lines_weights((double)step / (double)schedule, w);
    unsigned set = 0;
    for (int s = 0; s < WS_LINES_LEVELS; s++)
        if (w[s] != 0) set |= 1u << s;
    return set;
}

int ws_fit_time_boundaries(long total, long schedule, int lines, long first[WS_FIT_TIME_PHASES + 1],
                           int levels[WS_FIT_TIME_PHASES]) {
    if (schedule < 1) schedule = 1;
    int n = 1;
    first[0] = 0;
    /* the levels change at a handful of progress values: a scan of the
     * steps finds them (steps of equal levels are contiguous) */
    for (long s = 1; lines && s < total && n < WS_FIT_TIME_PHASES; s++)
        if (levels_at(s, schedule) != levels_at(s - 1, schedule)) first[n++] = s;
    first[n] = total;
    for (int k = 0; k < n; k++) {
        unsigned set = lines ? levels_at(first[k], schedule) : (1u << WS_LINES_LEVELS) - 1;
        levels[k] = 0;
        for (int b = 0; b < WS_LINES_LEVELS; b++) levels[k] += (set >> b) & 1;
    }
    return n;
}

int ws_fit_time_phases(ws_fit_time *t, long total, long schedule, int lines, ws_status *st) {
    memset(t, 0, sizeof *t);
    if (!(t->batch_steps = ws_calloc(total > 0 ? (size_t)total : 1, sizeof(float), "step times", st)))
        return st->code;
    t->total = total;
    t->schedule = schedule > 0 ? schedule : 1;
    t->wall_per_cpu = 1;
    int levels[WS_FIT_TIME_PHASES];
    t->n = ws_fit_time_boundaries(total, schedule, lines, t->first, levels);
    return WS_OK;
}

void ws_fit_time_free(ws_fit_time *t) {
    free(t->batch_steps);
    t->batch_steps = NULL;
}


static int phase_of(const ws_fit_time *t, long step) {
    int k = 0;
    while (k + 1 < t->n && step >= t->first[k + 1]) k++;
    return k;
}

/* grown (allocated as c): c's curves, each stretched about its middle by
 * `factor` (1: c's control points as they are). */
static void stretch(const ws_curves *c, double factor, ws_curves *grown) {
    grown->thickness = c->thickness;
    grown->overlap = c->overlap;
    memcpy(grown->P, c->P, (size_t)c->n * WS_CURVE_FLOATS * sizeof *c->P);
    for (int ci = 0; ci < c->n && factor != 1; ci++) {
        double mid[3];
        ws_curve_point(c, ci, 0.5, mid);
        double *P = grown->P + (size_t)ci * WS_CURVE_FLOATS;
        for (int k = 0; k < WS_CURVE_FLOATS; k++) P[k] = mid[k % 3] + factor * (P[k] - mid[k % 3]);
    }
}

int ws_fit_time_calibrate(ws_fit_time *t, ws_objective *obj, const ws_curves *c, double start_length,
                          const int *order, int n_train, int batch_size, const ws_rng *rng, double *grad,
                          ws_status *st) {
    ws_curves grown;
    if (ws_curves_alloc(&grown, c->n, st)) return st->code;
    double length = 0; /* c's, measured once: a phase's factor is its length over this */
    for (int ci = 0; ci < c->n; ci++) length += ws_curve_length(c, ci);
    /* The first WS_FIT_TIME_BATCHES batches, each called once untimed
     * first: a view's first call pays for what is then kept (its
     * hidden-line map, caches), which no later step pays again. */
    int nbatches = (n_train + batch_size - 1) / batch_size;
    if (nbatches > WS_FIT_TIME_BATCHES) nbatches = WS_FIT_TIME_BATCHES;
    if (ws_dist_size() > 1) nbatches = 1;
    /* each timed call's wall over CPU seconds: their median is the
     * timing's, one the machine stalled (a page fault, another process)
     * leaving it alone */
    double calls_cpu[WS_FIT_TIME_CALLS], walls_per_cpu[WS_FIT_TIME_PHASES * WS_FIT_TIME_CALLS];
    size_t timed = 0;
    int rc = WS_OK;
    for (int k = -1; k < t->n && !rc; k++) {
        int phase = k < 0 ? t->n - 1 : k; /* k = -1: the untimed first calls, in the last phase */
        long mid = (t->first[phase] + t->first[phase + 1]) / 2;
        double progress = (double)mid / (double)t->schedule;
        ws_objective_set_progress(obj, progress);
        const double grown_length = start_length * (1 + (WS_FIT_TIME_GROWTH - 1) * fmin(1, progress));
        stretch(c, length > 0 && grown_length > length ? grown_length / length : 1, &grown);
        double spent = 0;
        int calls = 0;
        int most = k < 0 ? nbatches : ws_dist_size() > 1 ? 1 : WS_FIT_TIME_CALLS;
        while (calls < most && (k < 0 || calls == 0 || spent < WS_FIT_TIME_CALIBRATION)) {
            /* the batches in turn: views differ in what they cost */
            int first = calls % nbatches * batch_size;
            int nviews = n_train - first < batch_size ? n_train - first : batch_size;
            ws_rng copy = *rng;
            double loss, w0 = ws_seconds(), c0 = ws_cpu_seconds();
            rc = ws_objective_batch(obj, &grown, order + first, nviews, &copy, &loss, grad, st);
            if (rc && rc != WS_ENUMERIC) break;
            rc = WS_OK;
            ws_status_clear(st); /* a non-finite loss costs what a finite one does */
            double used = ws_cpu_seconds() - c0;
            spent += used;
            if (k >= 0) {
                if (used > 0) walls_per_cpu[timed++] = (ws_seconds() - w0) / used;
                calls_cpu[calls] = used;
            }
            calls++;
        }
        /* the median: a call the machine's load interrupted is not the phase's cost */
        if (k >= 0 && !rc) t->model[k] = fmax(median(calls_cpu, (size_t)calls), 1e-9);
    }
    ws_curves_free(&grown);
    t->wall_per_cpu = timed ? median(walls_per_cpu, timed) : 1;
    return rc;
}

void ws_fit_time_add(ws_fit_time *t, long step, const double batch[2], const double all[2]) {
    int k = phase_of(t, step);
    t->batch_wall[k] += batch[0];
    t->batch_cpu[k] += batch[1];
    t->wall[k] += all[0];
    t->cpu[k] += all[1];
    t->steps[k]++;
    t->ratio[t->seen % WS_FIT_TIME_WINDOW] = batch[0] / t->model[k];
    t->seen++;
    if (step >= 0 && step < t->total) t->batch_steps[step] = (float)batch[1];
}

double ws_fit_time_left(const ws_fit_time *t, long from) {
    if (from >= t->total) return 0;
    int cur = phase_of(t, from);
    double recent[WS_FIT_TIME_WINDOW];
    size_t n = t->seen < WS_FIT_TIME_WINDOW ? (size_t)t->seen : WS_FIT_TIME_WINDOW;
    memcpy(recent, t->ratio, n * sizeof(double));
    double a = n ? median(recent, n) : t->wall_per_cpu;
    double besides = 0, work = 0;
    long steps = 0;
    for (int k = 0; k < t->n; k++) {
        besides += t->wall[k] - t->batch_wall[k];
        steps += t->steps[k];
    }
    besides = steps ? besides / steps : 0;
    for (int k = cur; k < t->n; k++) {
        long start = k == cur ? from : t->first[k];
        work += (double)(t->first[k + 1] - start) * (a * t->model[k] + besides);
    }
    return work;
}

/* "about 40 s", "about 12 min", "about 11 h". */
static void time_text(double seconds, char *text, size_t size) {
    if (seconds < 90)
        snprintf(text, size, "about %.0f s", fmax(1, seconds));
    else if (seconds < 90 * 60)
        snprintf(text, size, "about %.0f min", seconds / 60);
    else
        snprintf(text, size, "about %.0f h", seconds / 3600);
}

void ws_fit_time_announce(const ws_fit_time *t, long from, const ws_fit_options *opt, FILE *out) {
    double left = ws_fit_time_left(t, from);
    char text[64];
    time_text(left, text, sizeof text);
    fprintf(out, "fit: %ld steps, %s (%d phase%s of the schedule timed before the first step)\n",
            t->total - from, text, t->n, t->n > 1 ? "s" : "");
    if (left <= 3600) return;
    char more[96];
    if (ws_loss_uses_clip(&opt->loss))
        snprintf(more, sizeof more, "; --num-aug (now %d) for fewer images a step; --loss edges (no CLIP)",
                 opt->loss.num_aug);
    else
        snprintf(more, sizeof more, "; --size (now %d) for fewer pixels", opt->size);
    fprintf(out,
            "wiresketch: warning: %s on this machine; faster: --epochs (now %d), --inner-steps (now %d) or "
            "--max-steps N for fewer steps%s\n",
            text, opt->epochs, opt->inner_steps, more);
}

void ws_fit_time_print(const ws_fit_time *t, FILE *out) {
    double wall = 0, cpu = 0;
    for (int k = 0; k < t->n; k++) wall += t->wall[k], cpu += t->cpu[k];
    fprintf(out, "fit: wall per CPU second %.3g timed before the first step, %.3g over the steps\n", t->wall_per_cpu,
            cpu > 0 ? wall / cpu : NAN);
    for (int k = 0; k < t->n; k++) {
        fprintf(out, "fit: phase %d: steps %ld-%ld, modelled %.4g ms", k + 1, t->first[k], t->first[k + 1] - 1,
                1e3 * t->model[k]);
        long n = 0;
        double *v = t->steps[k] ? malloc((size_t)t->steps[k] * sizeof(double)) : NULL;
        for (long s = t->first[k]; v && s < t->first[k + 1] && n < t->steps[k]; s++)
            if (t->batch_steps[s] > 0) v[n++] = t->batch_steps[s];
        if (t->steps[k])
            fprintf(out,
                    ", measured %.4g ms CPU per step in the batch (median %.4g) + %.4g ms besides (%.4g ms wall in "
                    "all)\n",
                    1e3 * t->batch_cpu[k] / t->steps[k], n ? 1e3 * median(v, (size_t)n) : NAN,
                    1e3 * (t->cpu[k] - t->batch_cpu[k]) / t->steps[k], 1e3 * t->wall[k] / t->steps[k]);
        else
            fprintf(out, " CPU per step, not run here\n");
        free(v);
    }
}
