/* bench_bank.c: how far an augmentation bank's fixed transforms move a
 * view's expected gradient (bench.h, METHOD.md section 5).
 *
 * A step's gradient is the unaugmented item's plus A items under random
 * transforms: with fresh transforms its expectation over the draws is the
 * loss's own, and a fit averages the draws' noise away over the steps it
 * spends on a view. With a bank the A transforms are drawn from the view's
 * N fixed ones, so the expectation is the mean over those N, which misses
 * the fresh one by about sqrt(A / N) times one step's noise, the same
 * every time the view comes back. Measured: the mean gradient of `steps`
 * steps (other draws, the same sketch and view) of each setting, and the
 * spread of its steps around that mean. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench/bench.h"

/* What `steps` steps of one setting gave: their mean gradient and its
 * spread (sum over the components of the steps' variance). */
typedef struct {
    double *mean;
    double variance;
    double loss;
} setting_stats;

static int measure_setting(const ws_bench_bank_input *in, int aug_bank, uint64_t aug_seed, setting_stats *s,
                           ws_status *st) {
    int np = in->sketch->n * WS_CURVE_FLOATS;
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    lo.model = in->model;
    lo.aug_bank = aug_bank;
    lo.aug_seed = aug_seed;
    ws_splat_options so;
    ws_splat_options_default(&so);
    ws_objective *obj = NULL;
    double *grad = NULL, *sum2 = NULL;
    int rc = ws_objective_create(&obj, in->scene, &lo, &so, in->sketch->n, st);
    if (!rc && (!(s->mean = ws_calloc((size_t)np, sizeof(double), "bank benchmark", st)) ||
                !(grad = ws_malloc((size_t)np * sizeof(double), "bank benchmark", st)) ||
                !(sum2 = ws_calloc((size_t)np, sizeof(double), "bank benchmark", st))))
        rc = st->code;
    const int view = 0;
    s->loss = 0;
    for (int k = 0; k < in->steps && !rc; k++) {
        /* step k draws with the same generator in every setting */
        ws_rng rng;
        ws_rng_seed(&rng, 1000 + (uint64_t)k);
        double loss;
        if (ws_objective_batch(obj, in->sketch, &view, 1, &rng, &loss, grad, st)) {
            rc = st->code;
            break;
        }
        s->loss += loss / in->steps;
        for (int i = 0; i < np; i++) {
            s->mean[i] += grad[i] / in->steps;
            sum2[i] += grad[i] * grad[i];
        }
    }
    if (!rc) {
        /* the unbiased sample variance, summed over the components */
        double v = 0;
        for (int i = 0; i < np; i++) v += sum2[i] - in->steps * s->mean[i] * s->mean[i];
        s->variance = fmax(0.0, v / (in->steps - 1));
    }
    free(grad);
    free(sum2);
    ws_objective_free(obj);
    return rc;
}

static double norm(const double *a, const double *b, int n) {
    double s = 0;
    for (int i = 0; i < n; i++) s += (a[i] - (b ? b[i] : 0)) * (a[i] - (b ? b[i] : 0));
    return sqrt(s);
}

int ws_bench_bank(const ws_bench_bank_input *in, ws_bench_bank_row *rows, int nrows, ws_status *st) {
    if (in->steps < 2) return ws_fail(st, WS_EUSAGE, "bench bank: %d steps, at least 2 needed", in->steps);
    int np = in->sketch->n * WS_CURVE_FLOATS, rc = WS_OK;
    setting_stats fresh = {0}, *banked = ws_calloc((size_t)nrows, sizeof *banked, "bank benchmark", st);
    if (!banked) return st->code;
    rc = measure_setting(in, 0, 0, &fresh, st);
    for (int r = 0; r < nrows && !rc; r++) rc = measure_setting(in, rows[r].bank, rows[r].aug_seed, &banked[r], st);
    double ref = fmax(norm(fresh.mean, NULL, np), 1e-300);
    for (int r = 0; r < nrows && !rc; r++) {
        ws_bench_bank_row *row = &rows[r];
        const setting_stats *b = &banked[r];
        const setting_stats *against = row->against < 0 ? &fresh : &banked[row->against];
        ws_loss_options lo;
        ws_loss_options_default(&lo);
        row->num_aug = lo.num_aug;
        row->steps = in->steps;
        row->fresh_step_noise = sqrt(fresh.variance) / ref;
        row->difference = norm(b->mean, against->mean, np) / ref;
        row->difference_noise = sqrt((b->variance + against->variance) / in->steps) / ref;
        /* the sampling noise of the two means adds in squares to what the
         * bank moves; what is left is the bank's own bias */
        row->bias = sqrt(fmax(0.0, row->difference * row->difference - row->difference_noise * row->difference_noise));
        /* two banks each miss the fresh expectation independently */
        row->predicted = sqrt((row->against < 0 ? 1.0 : 2.0) * row->num_aug / row->bank) * row->fresh_step_noise;
        row->loss_difference = fabs(b->loss - against->loss) / fmax(fabs(against->loss), 1e-300);
    }
    for (int r = 0; r < nrows; r++) free(banked[r].mean);
    free(banked);
    free(fresh.mean);
    return rc;
}
