/* fit.c: the optimisation loop of `wiresketch fit` (see fit.h).
 *
 * One step: the batch's loss and gradient (objective.h: sample the curves
 * into Gaussians; for each view of the batch, splat, take the loss and its
 * gradient, splat backward, curve backward; average over the batch); refuse
 * the step if anything is not finite; Adam. The state that decides the
 * trajectory (control points, Adam moments, rng, position in the schedule)
 * lives in ws_fit_state and is what a checkpoint stores, so a resumed run
 * takes exactly the same steps.
 *
 * On several MPI ranks (base/distributed.h) every rank runs this loop on
 * the same state: the objective spreads each step's work and hands every
 * rank the same gradient. Rank 0 alone writes checkpoints, outputs and
 * messages; a stop request is agreed on at each step. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/paths.h"
#include "fit/checkpoint.h"
#include "fit/fit.h"
#include "fit/init.h"
#include "fit/respawn.h"
#include "fit/fit_outputs.h"
#include "fit/fit_time.h"
#include "base/distributed.h"
#include "base/outfile.h"
#include "base/progress.h"
#include "base/timing.h"
#include "io/scene.h"
#include "io/scene_crops.h"
#include "objective/objective.h"
#include "objective/view_targets.h"

volatile sig_atomic_t ws_fit_stop_requested = 0;

/* Everything one fit process holds. */
typedef struct {
    const ws_fit_options *opt; /* &in_effect */
    ws_fit_options in_effect;  /* the caller's, with --epochs and --n-curves auto resolved once the scene is loaded */
    ws_scene scene;
    ws_view_targets *targets; /* each view's silhouette and line target, made once for every user */
    ws_objective *objective;  /* sampling, splatting, the loss and their buffers */
    double *grad;             /* curves x WS_CURVE_FLOATS */
    double *backup;           /* 3 x curves x WS_CURVE_FLOATS: P, Adam m and v before an update */
    ws_fit_state s;
    ws_respawn *respawn;      /* NULL when --respawn-every is 0 (and not --init edges) */
    ws_line_evidence evidence; /* the hull's contours and creases, which the line targets keep */
    ws_edge_consensus consensus; /* the edges the views agree on, where they have no silhouette */
    ws_roi roi;               /* the region of interest the scene was loaded zoomed onto */
    ws_status roi_st;         /* why there is none (the scene's centre is in no train view), else clear */
    ws_scene_hull hull;       /* the training views' visual hull, carved once for the initial curves,
                               * the respawn and hidden-line removal (empty when none of them is on) */
    ws_progress progress;     /* the long steps before the first (loading, carving, voting) */
    double start;             /* ws_seconds() when this process began fitting */
    ws_fit_time time;         /* the schedule's phases and what their steps cost (fit_time.h) */
} fit_run;

/* Rank 0 speaks for the job (one rank: always). */
static int speaks(void) { return ws_dist_rank() == 0; }

static void shuffle(int *order, int n, ws_rng *rng) {
    for (int i = 0; i < n; i++) order[i] = i;
    for (int i = n - 1; i > 0; i--) {
        int j = (int)ws_rng_below(rng, (uint64_t)i + 1);
        int t = order[i];
        order[i] = order[j];
        order[j] = t;
    }
}

/* The batches of an epoch, the last one possibly short. */
static int batches_per_epoch(const fit_run *r) {
    int n = r->scene.split[WS_TRAIN].n, bs = r->opt->batch_size;
    return (n + bs - 1) / bs;
}

/* The steps of the epochs' schedule. */
static long schedule_steps(const fit_run *r) {
    return (long)r->opt->epochs * batches_per_epoch(r) * r->opt->inner_steps;
}

/* One Adam step on the views of a batch. A non-finite loss or gradient is
 * reported and the step refused: the control points and moments stay. */
static int train_step(fit_run *r, const int *views, int nviews, double *loss, ws_status *st) {
    int np = r->s.curves.n * WS_CURVE_FLOATS;
    /* over the epochs' schedule, not --max-steps: a run stopped early and
     * resumed sees the same progress at each step */
    ws_objective_set_progress(r->objective, (double)r->s.global_step / schedule_steps(r));
    int rc = ws_objective_batch(r->objective, &r->s.curves, views, nviews, &r->s.rng, loss, r->grad, st);
    if (rc && rc != WS_ENUMERIC) return rc;
    int finite = !rc && isfinite(*loss);
    for (int i = 0; i < np && finite; i++) finite = isfinite(r->grad[i]);
    if (!finite) {
        r->s.skipped_steps++;
        *loss = NAN;
        if (speaks())
            fprintf(stderr, "\nwiresketch: step %ld: non-finite loss or gradient (%s); step skipped\n",
                r->s.global_step, rc ? st->msg : "in the gradient");
        ws_status_clear(st);
        return WS_OK;
    }
    /* An update that leaves curves too long to sample (a huge step) is
     * undone, so the state always holds curves every later step, the
     * evaluation and the outputs can use. */
    ws_adam *adam = &r->s.adam;
    memcpy(r->backup, r->s.curves.P, np * sizeof(double));
    memcpy(r->backup + np, adam->m, np * sizeof(double));
    memcpy(r->backup + 2 * np, adam->v, np * sizeof(double));
    rc = ws_adam_update(adam, r->s.curves.P, r->grad)
             ? ws_fail(st, WS_ENUMERIC, "the gradient's square overflowed Adam's moments")
             : ws_objective_sample(r->objective, &r->s.curves, st);
    if (rc == WS_ENUMERIC) {
        memcpy(r->s.curves.P, r->backup, np * sizeof(double));
        memcpy(adam->m, r->backup + np, np * sizeof(double));
        memcpy(adam->v, r->backup + 2 * np, np * sizeof(double));
        adam->step--;
        r->s.skipped_steps++;
        if (speaks())
            fprintf(stderr, "\nwiresketch: step %ld: the update made the curves unusable (%s); step undone\n",
                r->s.global_step, st->msg);
        ws_status_clear(st);
        return WS_OK;
    }
    return rc;
}

/* The mean loss of a split's views, item 0 only (NaN for an empty split);
 * per_view (n, or NULL) receives each view's loss. */
static int evaluate(fit_run *r, int split, double *mean, double *per_view, ws_status *st) {
    int rc = ws_objective_split_mean(r->objective, &r->s.curves, split, per_view, mean, st);
    if (rc != WS_ENUMERIC) return rc;
    /* A non-finite evaluation is reported and recorded as NaN: it must not
     * cost the run its outputs. */
    if (speaks()) fprintf(stderr, "\nwiresketch: %s loss not finite (%s)\n", ws_split_names[split], st->msg);
    ws_status_clear(st);
    *mean = NAN;
    for (int v = 0; per_view && v < r->scene.split[split].n; v++) per_view[v] = NAN;
    return WS_OK;
}

static long total_steps(const fit_run *r) {
    long steps = schedule_steps(r);
    return r->opt->max_steps > 0 && r->opt->max_steps < steps ? r->opt->max_steps : steps;
}

/* The progress line on stderr: rewritten in place on a terminal, a line
 * every 10 seconds otherwise (logs stay readable); a last line at the end. */
static void progress(fit_run *r, double loss, double rate_start, long steps_this_run, int final) {
    static double last_print;
    double t = ws_seconds();
    int tty = isatty(2);
    if (r->opt->quiet || !speaks() || (!final && t - last_print < (tty ? 0.2 : 10.0))) return;
    last_print = t;
    double rate = steps_this_run / fmax(t - rate_start, 1e-9);
    char left[32], spent[32];
    ws_clock_text(ws_fit_time_left(&r->time, r->s.global_step), left);
    ws_clock_text(ws_fit_state_elapsed(&r->s, r->start), spent);
    int written;
    if (final)
        written = fprintf(stderr, "%sfit: %ld steps (%ld refused) in %s, %.2f steps/s, last loss %.6g\n",
                          tty ? "\r" : "", r->s.global_step, r->s.skipped_steps, spent, rate, loss);
    else
        written = fprintf(stderr, "%sepoch %d/%d batch %d/%d step %ld/%ld loss %.6g  %.2f steps/s  %s spent, %s left%s",
                          tty ? "\r" : "", r->s.epoch + 1, r->opt->epochs, r->s.batch_in_epoch + 1,
                          batches_per_epoch(r), r->s.global_step, total_steps(r), loss, rate, spent, left,
                          tty ? "   " : "\n");
    if (final && written >= 0) ws_fit_time_print(&r->time, stderr);
    /* A pipe whose reader went away (SIGPIPE is ignored: main.c) stops the
     * run as the signal would have, its outputs written. */
    if ((written < 0 || fflush(stderr) != 0) && errno == EPIPE && !ws_fit_stop_requested)
        ws_fit_stop_requested = SIGPIPE;
}

/* The state of a new fit: initial curves (fit/init.h), fresh Adam, first order. */
static int init_state(fit_run *r, ws_status *st) {
    const ws_fit_options *o = r->opt;
    ws_fit_state *s = &r->s;
    ws_rng_seed(&s->rng, o->seed);
    if (ws_fit_init_curves(o, &r->scene, &r->hull, &s->rng, &s->curves, st)) return st->code;
    /* No sampling check here: a loaded file's curves were measured by the
     * loader, and the random, hull and edge starts are strokes of bounded
     * size (the options' bounds, fit/init.h). */
    s->n_train = r->scene.split[WS_TRAIN].n;
    s->order = ws_malloc((size_t)s->n_train * sizeof(int), "view order", st);
    if (!s->order || ws_adam_init(&s->adam, s->curves.n * WS_CURVE_FLOATS, o->learning_rate, st))
        return st->code;
    /* --init edges: with fresh moments every curve is idle (no gradient
     * yet), so one respawn places them all on the photos' edges, each on
     * the edge pixel farthest from those already placed (fit/init.h) */
    int placed;
    if (!strcmp(o->init_curves, "edges") && ws_respawn_step(r->respawn, &s->curves, &s->adam, &placed, st))
        return st->code;
    shuffle(s->order, s->n_train, &s->rng);
    return ws_fit_state_snapshot(s, st);
}

static int save_checkpoint(fit_run *r, const char *const *argv, int argc, ws_status *st) {
    if (!speaks()) return WS_OK;
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/checkpoint.bin", r->opt->out_dir);
    ws_fit_state *s = &r->s;
    double before = s->elapsed;
    s->elapsed = ws_fit_state_elapsed(&r->s, r->start);
    int rc = ws_checkpoint_save(path, s, argc, argv, st);
    s->elapsed = before;
    return rc;
}

/* Marks the step as taken and moves through the schedule: end of batch
 * (validation), end of epoch (a new order). Nothing here draws from the rng
 * except the shuffle, which happens at the same point of every run. */
static int advance(fit_run *r, double loss, ws_status *st) {
    const ws_fit_options *o = r->opt;
    ws_fit_state *s = &r->s;
    s->global_step++;
    s->step_in_batch++;
    ws_log_row row = {s->global_batch, s->global_step, ws_fit_state_elapsed(&r->s, r->start), loss, NAN};
    if (s->step_in_batch == o->inner_steps) {
        s->step_in_batch = 0;
        s->batch_in_epoch++;
        s->global_batch++;
        if (o->eval_every > 0 && s->global_batch % o->eval_every == 0 &&
            evaluate(r, WS_VAL, &row.val_loss, NULL, st))
            return st->code;
        if (s->batch_in_epoch == batches_per_epoch(r)) {
            s->batch_in_epoch = 0;
            s->epoch++;
            if (s->epoch < o->epochs) shuffle(s->order, s->n_train, &s->rng);
        }
    }
    if (ws_fit_state_log(s, &row, st)) return st->code;
    if (o->snapshot_every > 0 && s->global_step % o->snapshot_every == 0) return ws_fit_state_snapshot(s, st);
    return WS_OK;
}

/* Moves idle curves every --respawn-every steps up to three quarters of
 * the schedule's own steps (fit/respawn.h). */
static int respawn(fit_run *r, ws_status *st) {
    const ws_fit_options *o = r->opt;
    ws_fit_state *s = &r->s;
    if (!r->respawn || o->respawn_every == 0 || s->global_step % o->respawn_every != 0 ||
        4 * s->global_step > 3 * schedule_steps(r))
        return WS_OK;
    int moved;
    if (ws_respawn_step(r->respawn, &s->curves, &s->adam, &moved, st)) return st->code;
    s->respawned += moved;
    return moved ? ws_objective_sample(r->objective, &s->curves, st) : WS_OK;
}

/* On several ranks, unless quiet: the bytes all ranks sent each other per
 * step since `before` (this rank's count then), for docs/RESULTS.md's scaling
 * table. */
static void report_traffic(const fit_run *r, size_t before, long steps) {
    int N = ws_dist_size();
    if (N == 1) return;
    size_t *sent = calloc((size_t)N, sizeof *sent), *bytes = malloc((size_t)N * sizeof *bytes);
    if (!sent || !bytes) ws_dist_abort("out of memory counting the traffic between ranks");
    sent[ws_dist_rank()] = ws_dist_bytes_sent() - before;
    for (int k = 0; k < N; k++) bytes[k] = sizeof *sent;
    ws_dist_allgather(sent, bytes);
    double total = 0;
    for (int k = 0; k < N; k++) total += (double)sent[k];
    if (speaks() && !r->opt->quiet && steps > 0)
        fprintf(stderr, "fit: %d ranks sent each other %.0f bytes per step\n", N, total / steps);
    free(sent);
    free(bytes);
}

static int run_schedule(fit_run *r, const char *const *argv, int argc, int *interrupted,
                        ws_status *st) {
    const ws_fit_options *o = r->opt;
    ws_fit_state *s = &r->s;
    size_t sent_before = ws_dist_bytes_sent();
    double rate_start = ws_seconds(), last_checkpoint = rate_start;
    long steps_this_run = 0;
    double loss = NAN;
    /* what the steps will take, timed before the first */
    if (ws_fit_time_phases(&r->time, total_steps(r), schedule_steps(r), o->loss.lines_weight != 0, st) ||
        ws_fit_time_calibrate(&r->time, r->objective, &s->curves, o->n_curves * o->length,
                              s->order, s->n_train, o->batch_size, &s->rng, r->grad, st))
        return st->code;
    if (speaks() && !o->quiet) ws_fit_time_announce(&r->time, s->global_step, o, stderr);
    rate_start = last_checkpoint = ws_seconds();
    double step_wall = rate_start, step_cpu = ws_cpu_seconds();
    while (s->epoch < o->epochs && !(o->max_steps > 0 && s->global_step >= o->max_steps)) {
        int stop = ws_dist_max(ws_fit_stop_requested);
        if (stop) {
            *interrupted = stop;
            break;
        }
        int first = s->batch_in_epoch * o->batch_size;
        int nviews = s->n_train - first < o->batch_size ? s->n_train - first : o->batch_size;
        double batch[2] = {ws_seconds(), ws_cpu_seconds()};
        if (train_step(r, s->order + first, nviews, &loss, st)) return st->code;
        batch[0] = ws_seconds() - batch[0];
        batch[1] = ws_cpu_seconds() - batch[1];
        if (advance(r, loss, st) || respawn(r, st)) return st->code;
        steps_this_run++;
        double wall = ws_seconds(), cpu = ws_cpu_seconds(), all[2] = {wall - step_wall, cpu - step_cpu};
        ws_fit_time_add(&r->time, s->global_step - 1, batch, all);
        step_wall = wall;
        step_cpu = cpu;
        progress(r, loss, rate_start, steps_this_run, 0);
        if (ws_seconds() - last_checkpoint > 60.0 * o->checkpoint_minutes) {
            if (save_checkpoint(r, argv, argc, st)) {
                /* past `ulimit -f` (SIGXFSZ came with the failure): the
                 * stop at the next step tries again and reports it */
                if (!ws_fit_stop_requested) return ws_dist_fail_alone(st);
                ws_status_clear(st);
                continue;
            }
            last_checkpoint = ws_seconds();
        }
    }
    progress(r, loss, rate_start, steps_this_run, 1);
    report_traffic(r, sent_before, steps_this_run);
    return WS_OK;
}

static void fit_run_free(fit_run *r) {
    ws_fit_time_free(&r->time);
    ws_respawn_free(r->respawn);
    ws_objective_free(r->objective);
    ws_view_targets_free(r->targets);
    ws_edge_consensus_free(&r->consensus);
    ws_line_evidence_free(&r->evidence);
    ws_scene_hull_free(&r->hull);
    free(r->grad);
    free(r->backup);
    ws_fit_state_free(&r->s);
    ws_scene_free(&r->scene);
}

/* What a fit writes its --resume must read: its last checkpoint, the
 * largest (every step's log row, every snapshot), must stay under the
 * reader's limit. Checked before the first step, where the options that
 * size it can still be changed. */
static int check_checkpoint_size(const fit_run *r, const char *const *argv, int argc, ws_status *st) {
    const ws_fit_options *o = r->opt;
    long steps = total_steps(r);
    long snapshots = 1 + (o->snapshot_every > 0 ? steps / o->snapshot_every : 0);
    /* --n-curves auto: the most it may choose, known before the consensus */
    const int n_curves = o->n_curves == WS_FIT_CURVES_AUTO ? WS_FIT_CURVES_SOLID : o->n_curves;
    double bytes = 8 + 4 + 4 + 4 + ws_checkpoint_state_bytes(n_curves, r->scene.split[WS_TRAIN].n, steps, snapshots);
    for (int i = 0; i < argc; i++) bytes += 4 + (double)strlen(argv[i]);
    if (bytes <= (double)WS_CHECKPOINT_MAX_BYTES) return WS_OK;
    return ws_fail(st, WS_EUSAGE,
                   "--n-curves %d: %ld steps keeping %ld snapshots (--snapshot-every %d) make a checkpoint of "
                   "%.3g bytes, over the %zu it may hold; lower --n-curves or --max-steps, or raise --snapshot-every",
                   n_curves, steps, snapshots, o->snapshot_every, bytes, WS_CHECKPOINT_MAX_BYTES);
}

static int fit_run_setup(fit_run *r, int resume, const char *const *argv, int argc, ws_status *st) {
    const ws_fit_options *o = r->opt;
    /* what the fit reads, which no output may replace (base/outfile.h) */
    const char *files[] = {o->init_curves, ws_loss_uses_clip(&o->loss) ? o->loss.weights_path : NULL};
    const char *folders[] = {o->scene_dir, o->edge_maps};
    if (ws_fit_options_check(o, st) || ws_outfile_protect(files, 2, folders, 2, st) ||
        ws_outfile_check(o->out_dir, st) || ws_fit_outputs_check(o->out_dir, st))
        return st->code;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = o->size;
    memcpy(so.background, o->background, sizeof so.background);
    so.background_auto = o->background_auto;
    so.edge_maps_dir = o->edge_maps;
    so.images_dir = o->images;
    so.masks_dir = o->masks;
    ws_progress_init(&r->progress);
    so.progress = speaks() && !o->quiet ? &r->progress : NULL;
    double box[6];
    if ((o->bbox && ws_roi_parse_bbox(o->bbox, box, st)) ||
        ws_roi_load_scene(&r->scene, o->scene_dir, &so, o->bbox ? box : NULL, &r->roi, &r->roi_st, st))
        return st->code;
    const int ntrain = r->scene.split[WS_TRAIN].n, epochs = ws_fit_epochs(o, ntrain);
    if (o->epochs == WS_FIT_EPOCHS_AUTO && epochs < WS_FIT_AUTO_EPOCHS && speaks() && !o->quiet)
        printf("fit: %d epochs over the %d train views (--epochs auto: %d up to %d views, past that about the "
               "steps of %d)\n",
               epochs, ntrain, WS_FIT_AUTO_EPOCHS, WS_FIT_AUTO_VIEWS, WS_FIT_AUTO_VIEWS);
    r->in_effect.epochs = epochs;
    if (check_checkpoint_size(r, argv, argc, st) ||
        ws_view_targets_create(&r->targets, &r->scene, st))
        return st->code;
    if (speaks() && ws_mkdir(o->out_dir, st)) return st->code;
    char crops[1024];
    ws_scene_crop_line(&r->scene, crops, sizeof crops);
    if (crops[0] && speaks() && !o->quiet) printf("%s\n", crops);
    ws_scene_mask_line(&r->scene, crops, sizeof crops);
    if (crops[0] && speaks() && !o->quiet) printf("%s\n", crops);
    if (resume) {
        char path[WS_PATH_MAX];
        snprintf(path, sizeof path, "%s/checkpoint.bin", o->out_dir);
        int ac;
        char **av;
        if (ws_checkpoint_load(path, &r->s, &ac, &av, st)) return st->code;
        ws_checkpoint_free_args(ac, av);
        if (r->s.n_train != r->scene.split[WS_TRAIN].n)
            return ws_fail(st, WS_EINPUT, "%s: made for %d training views, the scene has %d", path,
                           r->s.n_train, r->scene.split[WS_TRAIN].n);
        if (r->s.epoch < o->epochs &&
            (r->s.batch_in_epoch >= batches_per_epoch(r) || r->s.step_in_batch >= o->inner_steps))
            return ws_fail(st, WS_EUSAGE,
                           "%s: stopped at batch %d, step %d of its epoch, which --batch-size %d and "
                           "--inner-steps %d do not have; resume with the run's own values",
                           path, r->s.batch_in_epoch, r->s.step_in_batch, o->batch_size, o->inner_steps);
    } else if (!o->no_check) {
        char warning[WS_CHECK_LINE];
        if (ws_fit_check_scene(&r->scene, r->targets, warning, st)) return st->code;
        if (warning[0] && speaks())
            fprintf(stderr, "wiresketch: warning: %s\n", warning);
    }
    char consensus[WS_CHECK_LINE];
    if (ws_fit_consensus(&r->roi, &r->roi_st, &r->scene, r->targets, &r->consensus, consensus, st)) return st->code;
    if (consensus[0] && speaks() && !o->quiet)
        printf("%s; the silhouette term counts %.3g of --silhouette-weight with these silhouettes\n", consensus,
               WS_CONSENSUS_SILHOUETTE_SHARE);
    const int auto_curves = o->n_curves == WS_FIT_CURVES_AUTO;
    r->in_effect.n_curves = ws_fit_n_curves(o, r->consensus.solid);
    if (auto_curves && r->in_effect.n_curves != WS_FIT_CURVES && speaks() && !o->quiet)
        printf("fit: %d curves (--n-curves auto: %d, %d for a solid's edges)\n", r->in_effect.n_curves, WS_FIT_CURVES,
               WS_FIT_CURVES_SOLID);
    int edges_init = !resume && !strcmp(o->init_curves, "edges");
    int hull_init = edges_init || (!resume && !strcmp(o->init_curves, "hull"));
    const ws_silhouette *sil;
    if ((hull_init || o->respawn_every > 0 || o->loss.hidden_lines == WS_HIDDEN_HULL) &&
        (ws_view_targets_silhouettes(r->targets, WS_TRAIN, &sil, st) ||
         ws_scene_hull_make(&r->scene, WS_TRAIN, sil, WS_HULL_INIT_RESOLUTION, &r->hull, st)))
        return st->code;
    /* before the respawn and the loss ask for line targets */
    if (r->hull.surface.n && o->loss.lines_weight > 0) {
        if (ws_line_evidence_init(&r->evidence, &r->hull, st)) return st->code;
        ws_view_targets_set_evidence(r->targets, &r->evidence);
    }
    if (((o->respawn_every > 0 || edges_init) &&
         ws_respawn_create(&r->respawn, &r->scene, r->targets, &r->hull, o->n_curves, o->length, st)) ||
        (!resume && init_state(r, st)))
        return st->code;
    /* the Gaussian limit (base/limits.h) refused now, not in every step */
    ws_gaussians first = {0};
    int rc = ws_curves_sample(&r->s.curves, &first, st);
    ws_gaussians_free(&first);
    if (rc) return rc;
    ws_splat_options splat_opt;
    ws_splat_options_default(&splat_opt);
    splat_opt.cutoff = o->cutoff;
    ws_loss_options lo = o->loss;
    lo.aug_seed = o->seed; /* an augmentation bank follows the run's seed */
    lo.targets = r->targets;
    lo.hull = &r->hull;
    if (consensus[0]) lo.silhouette_weight *= WS_CONSENSUS_SILHOUETTE_SHARE;
    size_t np = (size_t)r->s.curves.n * WS_CURVE_FLOATS;
    /* before the objective, whose CLIP model and buffers make the fit's peak */
    if (lo.lines_weight == 0) ws_view_targets_release_setup(r->targets);
    if (ws_objective_create(&r->objective, &r->scene, &lo, &splat_opt, r->s.curves.n, st)) return st->code;
    if (!(r->grad = ws_malloc(np * sizeof(double), "control point gradient", st)) ||
        !(r->backup = ws_malloc(3 * np * sizeof(double), "control point backup", st)))
        return st->code;
    /* The first checkpoint only once everything loaded: a bad weight file
     * leaves no checkpoint behind. */
    return resume ? WS_OK : save_checkpoint(r, argv, argc, st);
}

/* *retire (curves, allocated): the curves the outputs leave out
 * (fit/respawn.h); none with --respawn-every 0, which leaves the curves
 * alone. */
static int retired_curves(const fit_run *r, int **retire, ws_status *st) {
    if (!(*retire = ws_calloc(r->s.curves.n ? r->s.curves.n : 1, sizeof(int), "retired curves", st)))
        return st->code;
    return r->respawn && r->opt->respawn_every > 0 ? ws_respawn_retire(r->respawn, &r->s.curves, *retire, st)
                                                   : WS_OK;
}

/* FNV-1a over bytes, continuing from h. */
static uint64_t fnv(uint64_t h, const void *data, size_t n) {
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

/* Every rank must start from the same state: a resumed rank that read
 * another checkpoint (an output directory that is not shared) would fit
 * something else. */
static int check_same_state(const fit_run *r, ws_status *st) {
    int N = ws_dist_size(), me = ws_dist_rank();
    if (N == 1) return WS_OK;
    const ws_fit_state *s = &r->s;
    size_t np = (size_t)s->curves.n * WS_CURVE_FLOATS;
    uint64_t h = fnv(14695981039346656037ull, &s->global_step, sizeof s->global_step);
    h = fnv(h, &s->rng, sizeof s->rng);
    h = fnv(h, s->curves.P, np * sizeof(double));
    h = fnv(h, s->adam.m, np * sizeof(double));
    h = fnv(h, s->adam.v, np * sizeof(double));
    h = fnv(h, s->order, (size_t)s->n_train * sizeof(int));
    uint64_t *all = ws_calloc((size_t)N, sizeof *all, "state fingerprints", st);
    size_t *bytes = all ? ws_malloc((size_t)N * sizeof *bytes, "state fingerprints", st) : NULL;
    if (!bytes) return ws_dist_fail_alone(st);
    all[me] = h;
    for (int k = 0; k < N; k++) bytes[k] = sizeof *all;
    ws_dist_allgather(all, bytes);
    int same = all[me] == all[0];
    free(all);
    free(bytes);
    if (same) return WS_OK;
    return ws_fail(st, WS_EINPUT,
                   "%s/checkpoint.bin: not the state rank 0 resumed from (every rank reads the checkpoint "
                   "at this path: the output directory must be shared, or the same file, on every machine)",
                   r->opt->out_dir);
}

int ws_fit(const ws_fit_options *opt, const char *const *argv, int argc, int resume,
           int *interrupted, ws_status *st) {
    fit_run r;
    memset(&r, 0, sizeof r);
    r.in_effect = *opt;
    r.opt = &r.in_effect;
    *interrupted = 0;
    r.start = ws_seconds();
    /* A failure one rank met alone in the setup (rank 0's output directory
     * or first checkpoint) reaches every rank before the next collective,
     * so that its line is the one printed, not a collective's mismatch. */
    int rc = ws_dist_agree(fit_run_setup(&r, resume, argv, argc, st), st);
    if (!rc) rc = ws_dist_agree(check_same_state(&r, st), st);
    if (!rc) rc = run_schedule(&r, argv, argc, interrupted, st);
    if (!rc) rc = save_checkpoint(&r, argv, argc, st);
    /* A stopped run writes every output it can: a checkpoint past the file
     * size limit does not cost the others. */
    ws_status stop_failure;
    ws_status_clear(&stop_failure);
    if (rc && *interrupted) {
        stop_failure = *st;
        ws_status_clear(st);
        rc = WS_OK;
    }
    double test_loss = NAN, *test_losses = NULL;
    if (!rc && !*interrupted) {
        test_losses = ws_calloc(r.scene.split[WS_TEST].n + 1, sizeof(double), "test losses", st);
        rc = test_losses ? evaluate(&r, WS_TEST, &test_loss, test_losses, st) : st->code;
    }
    int *retire = NULL;
    if (!rc && speaks()) rc = retired_curves(&r, &retire, st);
    if (!rc && speaks()) {
        r.s.elapsed = ws_fit_state_elapsed(&r.s, r.start);
        rc = ws_fit_write_outputs(r.opt, &r.scene, *interrupted ? NULL : r.targets, &r.s, retire, test_losses,
                                  test_loss, st);
    }
    free(retire);
    free(test_losses);
    fit_run_free(&r);
    if (stop_failure.code) {
        *st = stop_failure;
        rc = st->code;
    }
    return rc;
}
