/* cmd_fit.c: `wiresketch fit SCENE --out DIR [options]` and
 * `wiresketch fit --resume DIR`. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/paths.h"
#include "cli/args.h"
#include "fit/checkpoint.h"
#include "cli/cli_loss.h"
#include "cli/cli_rows.h"
#include "cli/cli_view.h"
#include "cli/commands.h"
#include "cli/run_record.h"
#include "fit/fit.h"
#include "io/report.h"
#include "objective/hidden_lines.h"
#include "base/distributed.h"
#include "base/runtime.h"

static void request_stop(int sig) { ws_fit_stop_requested = sig; }

/* The signals that stop a fit cleanly (fit.h), and how the last line names
 * them. SIGUSR1 is the one mpirun forwards; SIGPIPE stands for a progress
 * line whose reader went away (the signal itself is ignored: main.c). */
static const struct {
    int sig;
    const char *name;
} stop_signals[] = {
    {SIGINT, "SIGINT"},   {SIGTERM, "SIGTERM"}, {SIGHUP, "SIGHUP"},
    {SIGXCPU, "SIGXCPU (the CPU time limit, ulimit -t)"},
    {SIGXFSZ, "SIGXFSZ (the file size limit, ulimit -f)"},
    {SIGUSR1, "SIGUSR1"}, {SIGPIPE, "a broken pipe (the progress output's reader went away)"},
};

static const char *stop_name(int sig) {
    for (size_t k = 0; k < sizeof stop_signals / sizeof stop_signals[0]; k++)
        if (stop_signals[k].sig == sig) return stop_signals[k].name;
    return "a signal";
}

/* On several ranks SIGINT and SIGTERM (mpirun sends them when a rank has
 * died or the job is interrupted) end the process at once: a step's
 * collectives cannot finish without every rank. Rank 0 says so in one
 * line; SIGUSR1 (which mpirun forwards) stops cleanly instead. */
static char end_line[2 * WS_PATH_MAX + 300];
static size_t end_length;

/* The exit code once this rank's fit is over and its line printed (-1
 * before): a rank that ends first makes mpirun stop the others, which are
 * then only finishing, and they keep their code without the line. */
static volatile sig_atomic_t finished_code = -1;

static void end_now(int sig) {
    if (finished_code >= 0) _exit(finished_code);
    if (end_length && write(2, end_line, end_length) < 0) _exit(128 + sig);
    _exit(128 + sig);
}

static void install_end_handler(const char *out_dir) {
    if (ws_dist_rank() == 0) {
        int n = snprintf(end_line, sizeof end_line,
                         "\nwiresketch: the MPI job was ended (a rank died or mpirun was stopped); %s/checkpoint.bin "
                         "holds the last checkpoint: continue with `mpirun -np N wiresketch fit --resume %s`\n",
                         out_dir, out_dir);
        end_length = n > 0 && (size_t)n < sizeof end_line ? (size_t)n : 0;
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = end_now;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

/* A failure's line (on several ranks only one rank has one) and exit code. */
static int fail(const ws_status *st) { return st->msg[0] ? ws_cli_fail(st) : ws_exit_code(st); }

/* The report's settings table, made from the option list itself so that
 * it shows every option of the run (defaults included) and cannot drift
 * from it: one row per option but --resume, named as on the command line. */
#define MAX_SETTINGS 64
typedef struct {
    int n;
    ws_report_item items[MAX_SETTINGS];
    char text[MAX_SETTINGS][2][512];
    ws_arg_kind kind[MAX_SETTINGS];
    const char *loss;          /* the loss in effect (--loss auto's choice) */
    const char *loss_given;    /* --loss as given ("auto") */
    const char *config;        /* --config FILE, or NULL */
    int overwrite;             /* --overwrite */
} fit_settings;

static void fill_settings(const ws_arg *args, int nargs, fit_settings *out) {
    out->n = 0;
    for (int k = 0; k < nargs && out->n < MAX_SETTINGS; k++) {
        if (ws_run_record_invocation_option(args[k].name)) continue;
        out->kind[out->n] = args[k].kind;
        char(*text)[512] = out->text[out->n];
        snprintf(text[0], sizeof text[0], "%s", args[k].name + 2);
        ws_arg_value(&args[k], text[1], sizeof text[1]);
        out->items[out->n++] = (ws_report_item){.key = text[0], .value = text[1]};
    }
    /* not an option, but it decides the bits of a CLIP fit: OpenBLAS's
     * kernels differ in their rounding (OPENBLAS_CORETYPE, runtime.h) */
    if (out->n < MAX_SETTINGS) {
        const ws_blas_kernels *k = ws_runtime_kernels();
        char(*text)[512] = out->text[out->n];
        snprintf(text[0], sizeof text[0], "BLAS kernels");
        snprintf(text[1], sizeof text[1], "%s (%s)", k->after, k->why);
        out->items[out->n++] = (ws_report_item){.key = text[0], .value = text[1]};
    }
}

/* the parser's auto is the one the fit resolves (fit_options.h) */
_Static_assert(WS_ARG_AUTO == WS_FIT_EPOCHS_AUTO, "--epochs auto is the options' auto");
_Static_assert(WS_ARG_AUTO == WS_FIT_CURVES_AUTO, "--n-curves auto is the options' auto");

/* The defaults of the options a loss wants otherwise, where the command
 * line left them unset (NAN, -1): the original's for CLIP (no silhouette
 * term); for the line loss alone (`--loss edges`) those measured on the
 * solid scenes (docs/RESULTS.md, "Where it stands now"): thin strokes,
 * initial strokes long enough to span an edge but not two turns of a coil
 * (docs/RESULTS.md, "Initial strokes 0.15 long, not 0.3"), a small step,
 * and few steps per batch over more epochs (many steps in a row on one
 * view fit that view's own errors, such as the one line its line target
 * draws where two wires of the flat clip merge, and move whole wires off
 * their place; 24 epochs up to 96 train views, fewer past that:
 * fit_options.h), validated every 60 batches of 5 steps (validation is
 * costly; docs/USAGE.md, `fit`); and the silhouette term at weight 3,
 * measured on the shared rose and duck and the synthetic scenes
 * (docs/RESULTS.md, "Hull against random initialisation, and the
 * silhouette term"). */
static void loss_defaults(ws_fit_options *opt, const ws_fit_options *original) {
    int lines = opt->loss.lines_weight != 0 && !ws_loss_uses_clip(&opt->loss);
    if (isnan(opt->learning_rate)) opt->learning_rate = lines ? 0.0003 : original->learning_rate;
    if (isnan(opt->thickness)) opt->thickness = lines ? 0.01 : original->thickness;
    if (isnan(opt->length)) opt->length = lines ? 0.15 : original->length;
    if (isnan(opt->loss.silhouette_weight))
        opt->loss.silhouette_weight = lines ? 3 : original->loss.silhouette_weight;
    if (opt->epochs == WS_FIT_EPOCHS_AUTO && !lines) opt->epochs = original->epochs;
    if (opt->inner_steps == -1) opt->inner_steps = lines ? 5 : original->inner_steps;
    if (opt->eval_every == -1) opt->eval_every = lines ? 60 : original->eval_every;
}

/* The headings of `fit --help`; the table in parse_fit keeps its order,
 * which the report's settings and config.json follow. */
static const char *const input_options[] = {"--resume", "--config", "--size", "--background", "--edge-maps",
                                            "--images", "--masks", "--bbox", "--no-check", NULL};
static const char *const loss_options[] = {
    "--loss",           "--weights",           "--edges-weight",  "--silhouette-weight", "--clip-weight",
    "--clip-conv-loss", "--clip-fc-loss-weight", "--clip-conv-layer-weights", "--clip-geometric",
    "--hidden-lines",   "--num-aug",           "--aug-bank",      NULL};
static const char *const curve_options[] = {"--n-curves", "--init", "--thickness", "--radius",
                                            "--length",   "--overlap", "--cutoff", NULL};
static const char *const schedule_options[] = {"--batch-size", "--epochs",    "--inner-steps",   "--learning-rate",
                                               "--seed",       "--eval-every", "--max-steps",    "--respawn-every",
                                               NULL};
static const char *const output_options[] = {"--out", "--overwrite", "--checkpoint-minutes", "--snapshot-every",
                                             "--quiet", NULL};
static const char *const performance_options[] = {"--threads", "--precision", "--clip-batch", NULL};
static const ws_arg_group fit_groups[] = {
    {"input", input_options},       {"loss", loss_options},     {"curve", curve_options},
    {"schedule", schedule_options}, {"output", output_options}, {"performance", performance_options},
};

/* The words of a fit's command line that are no field of ws_fit_options:
 * names turned into options once parsed (apply_words), and what the
 * command does (--config, --overwrite). */
typedef struct {
    const char *loss, *background, *geometric, *hidden, *precision, *config;
    double edges_weight;
    int seed, overwrite;
    ws_arg_list layers;
} fit_words;

/* A new fit's words into opt, checked, and the loss's own defaults where
 * the command line left them unset (original: the options before any
 * was); settings (or NULL) receives the report's table, made from the
 * option table args once the words hold the values in effect. */
static int apply_words(fit_words *w, const ws_fit_options *original, const ws_arg *args, int nargs,
                       ws_fit_options *opt, fit_settings *settings, ws_status *st) {
    opt->seed = (uint64_t)(unsigned)w->seed;
    const char *loss_given = w->loss;
    w->loss = ws_cli_auto_loss(w->loss, opt->loss.weights_path);
    if (ws_cli_check_size(opt->size, st) ||
        ws_cli_background(w->background, opt->background, &opt->background_auto, st) ||
        ws_cli_choose_loss(w->loss, w->edges_weight, &w->layers, w->geometric, w->hidden, &opt->loss, st) ||
        ws_cli_choose_precision(w->precision, &opt->loss.precision, st) ||
        (loss_defaults(opt, original), ws_fit_options_check(opt, st)))
        return st->code;
    if (settings) {
        /* the layer weights in effect, also when the defaults are */
        w->layers.n = opt->loss.n_layer_weights;
        w->hidden = ws_hidden_mode_names[opt->loss.hidden_lines];
        memcpy(w->layers.v, opt->loss.layer_weights, sizeof(double) * w->layers.n);
        settings->loss = w->loss;
        settings->loss_given = loss_given;
        fill_settings(args, nargs, settings);
        opt->settings = settings->items;
        opt->n_settings = settings->n;
    }
    return WS_OK;
}

/* Parses the fit's own arguments (those of a new run, or those a checkpoint
 * stored) into opt; settings (or NULL) receives the report's table. */
static int parse_fit(int argc, char **argv, ws_fit_options *opt, const char **resume_dir, int *help,
                     fit_settings *settings, ws_status *st) {
    ws_fit_options_default(opt);
    const ws_fit_options original = *opt;
    /* unset: loss_defaults */
    opt->learning_rate = opt->thickness = opt->length = opt->loss.silhouette_weight = NAN;
    opt->epochs = WS_FIT_EPOCHS_AUTO; /* --epochs auto reads as this too */
    opt->inner_steps = opt->eval_every = -1;
    fit_words w = {.loss = "auto", .background = "black", .geometric = "blocks", .precision = "auto",
                   .edges_weight = 1.0};
    *resume_dir = NULL;
    opt->out_dir = "out";
    const ws_arg args[] = {
        {"--out", WS_ARG_STRING, &opt->out_dir, 0, "output directory [out]"},
        {"--resume", WS_ARG_STRING, resume_dir, 0, "continue the fit whose output directory is DIR"},
        {"--overwrite", WS_ARG_FLAG, &w.overwrite, 0, "replace another run's outputs in --out (refused otherwise)"},
        {"--config", WS_ARG_STRING, &w.config, 0,
         "run the fit that FILE (a run's config.json) records again; options after it override"},
        WS_ROW_LOSS(&w.loss),
        WS_ROW_WEIGHTS(&opt->loss.weights_path),
        WS_ROW_EDGES_WEIGHT(&w.edges_weight),
        {"--silhouette-weight", WS_ARG_DOUBLE, &opt->loss.silhouette_weight, 0,
         "weight of the silhouette term over the training views (a third of it counts where they have no usable "
         "silhouette) [0; 3 with --loss edges]"},
        {"--batch-size", WS_ARG_INT, &opt->batch_size, 0, "views per batch [1]"},
        {"--epochs", WS_ARG_INT_AUTO, &opt->epochs, 0,
         "passes over the training views, or auto [auto: 10; with --loss edges 24, fewer past 96 views]"},
        {"--inner-steps", WS_ARG_INT, &opt->inner_steps, 0, "Adam steps per batch [30; 5 with --loss edges]"},
        {"--learning-rate", WS_ARG_DOUBLE, &opt->learning_rate, 0, "Adam step size [0.005; 0.0003 with --loss edges]"},
        {"--n-curves", WS_ARG_INT_AUTO, &opt->n_curves, 0,
         "number of curves, or auto [auto: 25; 35 for a solid outlined by the edges the views agree on]"},
        {"--thickness", WS_ARG_DOUBLE, &opt->thickness, 0, "Gaussian radius, world units [0.02; 0.01 with --loss edges]"},
        {"--radius", WS_ARG_DOUBLE, &opt->radius, 0, "initialisation sphere radius [0.8]"},
        {"--length", WS_ARG_DOUBLE, &opt->length, 0, "initial curve length [0.02; 0.15 with --loss edges]"},
        {"--overlap", WS_ARG_DOUBLE, &opt->overlap, 0, "Gaussian overlap [0.6]"},
        {"--clip-weight", WS_ARG_DOUBLE, &opt->loss.global_weight, 0, "global term weight [1]"},
        WS_ROW_CONV_WEIGHT(&opt->loss.conv_weight),
        WS_ROW_FC_WEIGHT(&opt->loss.fc_weight),
        WS_ROW_LAYER_WEIGHTS(&w.layers),
        WS_ROW_GEOMETRIC(&w.geometric),
        WS_ROW_HIDDEN(&w.hidden),
        {"--num-aug", WS_ARG_INT, &opt->loss.num_aug, 0, "augmentations per view and step [4]"},
        {"--aug-bank", WS_ARG_INT, &opt->loss.aug_bank, 0,
         "N fixed transforms per view, photo features cached; 0 = fresh every step [0]"},
        WS_ROW_PRECISION(&w.precision),
        {"--clip-batch", WS_ARG_INT, &opt->loss.pass_items, 0,
         "stroke images per CLIP pass, the unit of work of an MPI rank; 0 = 1 + num-aug [0]"},
        WS_ROW_SIZE(&opt->size),
        WS_ROW_BACKGROUND(&w.background),
        WS_ROW_EDGE_MAPS(&opt->edge_maps),
        WS_ROW_IMAGES(&opt->images),
        WS_ROW_MASKS(&opt->masks),
        WS_ROW_BBOX(&opt->bbox),
        WS_ROW_CUTOFF(&opt->cutoff),
        {"--seed", WS_ARG_INT, &w.seed, 0, "random seed [0]"},
        WS_ROW_THREADS(&opt->threads),
        {"--eval-every", WS_ARG_INT, &opt->eval_every, 0, "validate every N batches, 0 = never [10; 60 with --loss edges]"},
        {"--max-steps", WS_ARG_INT, &opt->max_steps, 0, "stop after N steps in all, 0 = schedule [0]"},
        {"--checkpoint-minutes", WS_ARG_DOUBLE, &opt->checkpoint_minutes, 0, "checkpoint interval [5]"},
        {"--snapshot-every", WS_ARG_INT, &opt->snapshot_every, 0, "steps per evolution.gif frame [30]"},
        {"--respawn-every", WS_ARG_INT, &opt->respawn_every, 0,
         "steps between moves of idle curves onto photo edges no curve covers, 0 = never [300]"},
        {"--init", WS_ARG_STRING, &opt->init_curves, 0,
         "hull (on the visual hull), edges (on the photos' edges), random (the original's sphere) "
         "or a curve file [hull]"},
        {"--no-check", WS_ARG_FLAG, &opt->no_check, 0, "fit even a scene `check` finds inconsistent (a focal estimate alone, or no usable silhouette, only warns)"},
        {"--quiet", WS_ARG_FLAG, &opt->quiet, 0, "no progress line"},
    };
    const ws_command_spec spec = {
        "fit SCENE [--out DIR] [options] | fit --resume DIR [options that override]",
        "fit 3D curves to a multi-view scene (docs/METHOD.md sections 5-7)", args,
        (int)(sizeof args / sizeof args[0]), 0, 1, fit_groups, (int)(sizeof fit_groups / sizeof fit_groups[0])};
    const char *pos[1];
    int npos;
    if (ws_args_parse(&spec, argc, argv, pos, &npos, help, st) || *help) return st->code;
    if (settings) {
        settings->config = w.config;
        settings->overwrite = w.overwrite;
    }
    if (*resume_dir || w.config) return WS_OK;
    if (npos != 1) return ws_fail(st, WS_EUSAGE, "fit: missing SCENE (usage: wiresketch %s)", spec.usage);
    opt->scene_dir = pos[0];
    return apply_words(&w, &original, args, spec.nargs, opt, settings, st);
}

/* A checkpoint's stored arguments are input like the command line: they
 * must be a complete new fit on their own (a SCENE, every value in range),
 * parsed and checked by parse_fit as a command line is; --resume or --help
 * among them (which no run stores) mark a crafted file. Files they name
 * (--weights, --init) may have moved since: those are checked when the
 * resumed run, with its overrides, uses them. */
static int check_stored_arguments(const char *path, int argc, char **argv, ws_status *st) {
    for (int i = 0; i < argc; i++)
        if (!strcmp(argv[i], "--resume") || !strcmp(argv[i], "--config") || !strcmp(argv[i], "--help") ||
            !strcmp(argv[i], "-h"))
            return ws_fail(st, WS_EINPUT, "%s: stored arguments contain %s", path, argv[i]);
    ws_fit_options stored;
    const char *resume_dir;
    int help;
    if (parse_fit(argc, argv, &stored, &resume_dir, &help, NULL, st) == WS_EUSAGE) {
        char why[sizeof st->msg];
        snprintf(why, sizeof why, "%s", st->msg);
        return ws_fail(st, WS_EINPUT, "%s: stored arguments: %s", path, why);
    }
    ws_status_clear(st);
    return WS_OK;
}

/* The arguments of a new fit (those after `fit`), parsed and checked as
 * the command would, without running it: a sweep checks every run's
 * arguments before the first starts. */
int cmd_fit_check_arguments(int argc, char **argv, ws_status *st) {
    ws_fit_options opt;
    const char *resume_dir;
    int help;
    if (parse_fit(argc, argv, &opt, &resume_dir, &help, NULL, st)) return st->code;
    if (resume_dir) return ws_fail(st, WS_EUSAGE, "--resume: not an option of a new fit");
    return WS_OK;
}

/* Options a resumed run cannot change: the checkpoint's curves, Adam
 * moments (which hold the step size) and generator already embody them, so
 * a new value would be ignored; it is refused instead. */
static int fixed_on_resume(const char *arg, ws_status *st) {
    static const char *const fixed[] = {"--learning-rate", "--n-curves", "--thickness", "--radius",
                                        "--length", "--overlap", "--init", "--seed"};
    for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; k++)
        if (ws_arg_same_name(arg, fixed[k]))
            return ws_fail(st, WS_EUSAGE, "%s: fixed by the checkpoint of the run being resumed; "
                                          "start a new fit to change it", fixed[k]);
    return WS_OK;
}

/* The arguments of a run: the saved ones (nsaved of saved), then those
 * given now but `skip` and its value, so that later ones override (e.g. a
 * larger --max-steps); fixed: refuse those fixed_on_resume names. The
 * strings stay owned by saved/argv. */
static int append_given(int nsaved, char **saved, int argc, char **argv, const char *skip, int fixed,
                        int *run_argc, char ***run_argv, ws_status *st) {
    *run_argv = ws_calloc((size_t)(nsaved + argc + 1), sizeof(char *), "arguments", st);
    if (!*run_argv) return st->code;
    int n = 0;
    for (int i = 0; i < nsaved; i++) (*run_argv)[n++] = saved[i];
    for (int i = 0; i < argc; i++) {
        if (ws_arg_same_name(argv[i], skip)) {
            i++;
            continue;
        }
        if (fixed && fixed_on_resume(argv[i], st)) return st->code;
        (*run_argv)[n++] = argv[i];
    }
    *run_argc = n;
    return WS_OK;
}

/* The arguments of a resumed run: those its checkpoint stored, then the
 * ones given now except --resume DIR. */
static int resume_arguments(const char *dir, int argc, char **argv, int *run_argc, char ***run_argv,
                            int *nsaved, char ***saved, ws_status *st) {
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    if (access(path, F_OK) != 0) return ws_fail(st, WS_EINPUT, "%s: no checkpoint to resume from", path);
    if (ws_checkpoint_load(path, NULL, nsaved, saved, st) || check_stored_arguments(path, *nsaved, *saved, st))
        return st->code;
    return append_given(*nsaved, *saved, argc, argv, "--resume", 1, run_argc, run_argv, st);
}

/* The arguments of a run of config.json FILE: those it records, then the
 * ones given now except --config FILE. */
static int config_arguments(const char *file, int argc, char **argv, int *run_argc, char ***run_argv,
                            int *nsaved, char ***saved, ws_status *st) {
    if (ws_run_record_read(file, nsaved, saved, st) || check_stored_arguments(file, *nsaved, *saved, st))
        return st->code;
    return append_given(*nsaved, *saved, argc, argv, "--config", 0, run_argc, run_argv, st);
}

/* Rank 0: DIR/config.json, the record of this run (cli/run_record.h), in
 * the output directory the fit made. */
static int write_record(const ws_fit_options *opt, const fit_settings *settings, int argc, char **argv,
                        ws_status *st) {
    if (ws_dist_rank() > 0) return WS_OK;
    const char **line = ws_calloc((size_t)argc + 2, sizeof *line, "command line", st);
    if (!line) return st->code;
    line[0] = "wiresketch";
    line[1] = "fit";
    for (int i = 0; i < argc; i++) line[i + 2] = argv[i];
    int rc = ws_run_record_write(opt->out_dir, opt->scene_dir, argc + 2, line, settings->items, settings->kind,
                                 settings->n, st);
    free(line);
    return rc ? st->code : WS_OK;
}

static int fit_command(int argc, char **argv) {
    ws_status st;
    ws_status_clear(&st);
    /* Installed first: a signal during start-up also ends the run cleanly. */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = request_stop;
    for (size_t k = 0; k < sizeof stop_signals / sizeof stop_signals[0]; k++)
        if (stop_signals[k].sig != SIGPIPE) sigaction(stop_signals[k].sig, &sa, NULL);
    ws_fit_options opt;
    const char *resume_dir;
    int help;
    static fit_settings settings;
    int rc = parse_fit(argc, argv, &opt, &resume_dir, &help, &settings, &st);
    if (rc) return ws_dist_rank() == 0 ? ws_cli_fail(&st) : ws_exit_code(&st);
    if (help) {
        printf("\n%s", ws_exit_status_text);
        return 0;
    }
    int run_argc = argc, nsaved = 0, interrupted = 0, from_record = settings.config != NULL;
    int overwrite = settings.overwrite;
    char **run_argv = argv, **saved = NULL, **final_argv = NULL;
    const char *dir = resume_dir;
    if (dir) {
        rc = resume_arguments(dir, argc, argv, &run_argc, &run_argv, &nsaved, &saved, &st);
        if (!rc) rc = parse_fit(run_argc, run_argv, &opt, &resume_dir, &help, &settings, &st);
        opt.out_dir = dir; /* the run continues where its checkpoint is now */
    } else if (from_record) {
        rc = config_arguments(settings.config, argc, argv, &run_argc, &run_argv, &nsaved, &saved, &st);
        if (!rc) rc = parse_fit(run_argc, run_argv, &opt, &resume_dir, &help, &settings, &st);
        overwrite |= settings.overwrite;
    }
    /* a new run stores the loss `auto` chose with its arguments, so that
     * resuming it keeps that loss whatever weight files exist by then */
    if (!rc && !dir &&
        (final_argv = ws_calloc((size_t)run_argc + 3, sizeof(char *), "arguments", &st)) != NULL) {
        memcpy(final_argv, run_argv, (size_t)run_argc * sizeof(char *));
        final_argv[run_argc] = "--loss";
        final_argv[run_argc + 1] = (char *)settings.loss;
    } else if (!rc && !dir) {
        rc = st.code;
    }
    if (!rc && !dir && !overwrite && ws_dist_rank() == 0) rc = ws_run_record_check_free(opt.out_dir, &st);
    if (!rc) rc = ws_runtime_init(opt.threads, &st);
    rc = ws_dist_agree(rc, &st);
    if (ws_dist_size() > 1) install_end_handler(opt.out_dir);
    if (!rc && ws_dist_rank() == 0) ws_cli_announce_loss(settings.loss_given, opt.loss.weights_path);
    if (!rc) {
        rc = ws_fit(&opt, (const char *const *)(final_argv ? final_argv : run_argv), final_argv ? run_argc + 2 : run_argc,
                    dir != NULL, &interrupted, &st);
    }
    /* beside the outputs, which exist now (also those of an interrupted run) */
    if (!rc) rc = write_record(&opt, &settings, argc, argv, &st);
    free(final_argv);
    if ((dir || from_record) && run_argv != argv) free(run_argv);
    if (from_record)
        ws_run_record_free_args(nsaved, saved);
    else
        ws_checkpoint_free_args(nsaved, saved);
    if (interrupted) {
        /* 128 + the signal, as a shell reports a process the signal ended
         * (130 for Ctrl-C), so that `fit ... && export ...` stops there */
        if (ws_dist_rank() == 0) {
            if (rc)
                fprintf(stderr, "wiresketch: stopped by %s; %s; what could be written is in %s; continue "
                                "with `wiresketch fit --resume %s`\n",
                        stop_name(interrupted), st.msg, opt.out_dir, opt.out_dir);
            else
                fprintf(stderr, "wiresketch: stopped by %s; outputs and checkpoint written to %s; continue "
                                "with `wiresketch fit --resume %s`\n",
                        stop_name(interrupted), opt.out_dir, opt.out_dir);
        }
        return 128 + interrupted;
    }
    if (rc) return fail(&st);
    if (ws_dist_rank() > 0) return 0;
    fprintf(stderr, "wiresketch: done; see %s/report.html\n", opt.out_dir);
    return 0;
}

/* Every rank of an MPI job runs the fit (base/distributed.h). */
int cmd_fit(int argc, char **argv) {
    ws_status st;
    ws_status_clear(&st);
    if (ws_dist_init(&st)) return ws_cli_fail(&st);
    int rc = fit_command(argc, argv);
    finished_code = rc;
    ws_dist_finalize();
    return rc;
}
