/* fit_options.c: the defaults and the one check of a fit's options (see
 * fit_options.h).
 *
 * The bounds keep every count the schedule multiplies (views per batch x
 * batches x inner steps x epochs, as a long) and every allocation sized by
 * an option far from overflow, and refuse values that cannot describe a
 * fit (a negative count, a zero thickness) before anything is loaded. */
#include <string.h>
#include "base/runtime.h"
#include "fit/fit_options.h"
#include "geometry/roi.h"

void ws_fit_options_default(ws_fit_options *o) {
    memset(o, 0, sizeof *o);
    ws_loss_options_default(&o->loss);
    o->size = 224;
    o->batch_size = 1;
    o->epochs = 10;
    o->inner_steps = 30;
    o->n_curves = WS_FIT_CURVES_AUTO;
    o->eval_every = 10;
    o->threads = 0;
    o->learning_rate = 0.005;
    o->thickness = 0.02;
    o->radius = 0.8;
    o->length = 0.02;
    o->overlap = 0.6;
    o->cutoff = 4.0;
    o->seed = 0;
    o->checkpoint_minutes = 5.0;
    o->snapshot_every = 30;
    o->respawn_every = 300;
    o->init_curves = "hull";
}

int ws_fit_n_curves(const ws_fit_options *o, int solid) {
    if (o->n_curves != WS_FIT_CURVES_AUTO) return o->n_curves;
    return solid ? WS_FIT_CURVES_SOLID : WS_FIT_CURVES;
}

int ws_fit_epochs(const ws_fit_options *o, int ntrain) {
    if (o->epochs != WS_FIT_EPOCHS_AUTO) return o->epochs;
    if (ntrain <= WS_FIT_AUTO_VIEWS) return WS_FIT_AUTO_EPOCHS;
    return (WS_FIT_AUTO_EPOCHS * WS_FIT_AUTO_VIEWS + ntrain - 1) / ntrain;
}

/* Counts: views per batch, epochs and Adam steps per batch at most 10^6
 * (their product with 65536 batches stays below 2^63), curves at most 10^5
 * (WS_CURVE_FLOATS numbers each, Gaussians per curve capped). Lengths (world
 * units): at most 10^6, far beyond any scene yet finite when squared. */
#define MAX_COUNT 1000000
#define MAX_CURVES 100000
#define MAX_WORLD 1e6

int ws_fit_options_check(const ws_fit_options *o, ws_status *st) {
    if (!o->scene_dir) return ws_fail(st, WS_EUSAGE, "fit: no SCENE given");
    double box[6];
    if (o->bbox && ws_roi_parse_bbox(o->bbox, box, st)) return st->code;
    if (o->batch_size < 1 || o->batch_size > MAX_COUNT)
        return ws_fail(st, WS_EUSAGE, "--batch-size: %d is not in [1, %d]", o->batch_size, MAX_COUNT);
    if ((o->epochs < 0 && o->epochs != WS_FIT_EPOCHS_AUTO) || o->epochs > MAX_COUNT)
        return ws_fail(st, WS_EUSAGE, "--epochs: %d is not in [0, %d]", o->epochs, MAX_COUNT);
    if (o->inner_steps < 1 || o->inner_steps > MAX_COUNT)
        return ws_fail(st, WS_EUSAGE, "--inner-steps: %d is not in [1, %d]", o->inner_steps, MAX_COUNT);
    if ((o->n_curves < 1 && o->n_curves != WS_FIT_CURVES_AUTO) || o->n_curves > MAX_CURVES)
        return ws_fail(st, WS_EUSAGE, "--n-curves: %d is not in [1, %d]", o->n_curves, MAX_CURVES);
    /* no upper bound: a step that throws the curves out is undone and
     * reported (fit.c), whatever its size */
    if (!(o->learning_rate > 0))
        return ws_fail(st, WS_EUSAGE, "--learning-rate: %g is not positive", o->learning_rate);
    if (!(o->thickness > 0 && o->thickness <= MAX_WORLD))
        return ws_fail(st, WS_EUSAGE, "--thickness: %g is not in (0, %g]", o->thickness, MAX_WORLD);
    if (!(o->radius >= 0 && o->radius <= MAX_WORLD))
        return ws_fail(st, WS_EUSAGE, "--radius: %g is not in [0, %g]", o->radius, MAX_WORLD);
    if (!(o->length >= 0 && o->length <= MAX_WORLD))
        return ws_fail(st, WS_EUSAGE, "--length: %g is not in [0, %g]", o->length, MAX_WORLD);
    if (!(o->overlap >= 0 && o->overlap < 1))
        return ws_fail(st, WS_EUSAGE, "--overlap: %g is not in [0, 1)", o->overlap);
    if (o->max_steps < 0 || o->eval_every < 0 || o->snapshot_every < 0)
        return ws_fail(st, WS_EUSAGE, "--max-steps, --eval-every and --snapshot-every must be >= 0");
    if (o->respawn_every < 0)
        return ws_fail(st, WS_EUSAGE, "--respawn-every: %d is negative", o->respawn_every);
    if (!(o->checkpoint_minutes > 0))
        return ws_fail(st, WS_EUSAGE, "--checkpoint-minutes: %g is not positive", o->checkpoint_minutes);
    if (ws_runtime_check_threads(o->threads, st)) return st->code;
    return ws_loss_options_check(&o->loss, st);
}
