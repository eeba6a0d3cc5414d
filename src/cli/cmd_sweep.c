/* cmd_sweep.c: `wiresketch sweep SCENE --out DIR --vary NAME=V1,V2,...
 * [--vary ...] [fit options]`: one fit per combination of the varied
 * values, then a contact sheet and a page that show every run's test
 * renders side by side with the photos, with its metrics and time.
 *
 * Each run is a child `wiresketch fit SCENE --out DIR/RUN [fit options]
 * --NAME VALUE ...` (the varied values come last, so they win over the
 * same option among the fit options), RUN naming its values
 * ("n_curves=10,thickness=0.03"). Resumable: a run that finished has
 * DIR/RUN/sweep.done and is skipped; one with a checkpoint and no
 * sweep.done continues with `fit --resume`. An interrupt (Ctrl-C) reaches
 * the running fit, which checkpoints; the sweep then stops, and the same
 * command continues it. */
#include <errno.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "base/outfile.h"
#include "base/paths.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "io/sweep_page.h"
#include "nn/base/bytes.h"

extern char **environ;

#define MAX_VARY 8
#define MAX_VALUES 32
#define MAX_RUNS 1024
/* a run's folder name, "n_curves=10,thickness=0.03" */
#define RUN_NAME_MAX 1024

typedef struct {
    char name[64];
    int n;
    char value[MAX_VALUES][64];
} vary_axis;

typedef struct {
    const char *scene, *out;
    int nvary;
    vary_axis vary[MAX_VARY];
    int nfit;
    char **fit_args; /* passed through to every fit */
    int views, cell; /* contact sheet: test views shown, pixels per cell */
} sweep_plan;

/* The signal that stopped the sweep (0: none): the running fit received
 * it too (or alone) and stopped cleanly (fit.h). */
static volatile sig_atomic_t sweep_stop;
static void on_signal(int sig) { sweep_stop = sig; }

static int usage_help(void) {
    printf("usage: wiresketch sweep SCENE --out DIR --vary NAME=V1,V2,... [--vary ...] [fit options]\n"
           "One fit per combination of the varied values (each in DIR/NAME=V,...; resumable),\n"
           "then DIR/contact_sheet.png and DIR/index.html: every run's test renders side by\n"
           "side with the photos, with its metrics and time.\n\n"
           "options:\n"
           "  --out DIR                   output directory (required)\n"
           "  --vary NAME=V1,V2,...       a fit option and its values; repeat for a grid\n"
           "  --sheet-views N             test views shown per run [6]\n"
           "  --sheet-cell N              pixels per image in the contact sheet [128]\n"
           "  (any other option)          passed to every fit (see wiresketch fit --help)\n");
    return 0;
}

static int parse_vary(const char *text, vary_axis *a, ws_status *st) {
    const char *eq = strchr(text, '=');
    size_t len = eq ? (size_t)(eq - text) : 0;
    if (!eq || len == 0 || len >= sizeof a->name || !eq[1])
        return ws_fail(st, WS_EUSAGE, "--vary: '%s' is not NAME=V1,V2,...", text);
    memcpy(a->name, text, len);
    a->name[len] = '\0';
    for (const char *c = a->name; *c; c++)
        if (!(*c == '_' || *c == '-' || (*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9')))
            return ws_fail(st, WS_EUSAGE, "--vary: '%s' is not an option name", a->name);
    /* the sweep's own: a run's output directory is DIR/NAME=V,..., where
     * its sweep.done and the summary look for it */
    if (ws_arg_same_name(a->name, "out"))
        return ws_fail(st, WS_EUSAGE, "--vary %s: the sweep sets every run's --out (DIR/NAME=V,...)", a->name);
    a->n = 0;
    for (const char *v = eq + 1; *v;) {
        size_t n = strcspn(v, ",");
        if (n == 0 || n >= sizeof a->value[0] || a->n == MAX_VALUES)
            return ws_fail(st, WS_EUSAGE, "--vary %s: an empty, too long or %dth value", a->name,
                           MAX_VALUES + 1);
        for (size_t k = 0; k < n; k++)
            if (v[k] == '/' || (unsigned char)v[k] < 0x20)
                return ws_fail(st, WS_EUSAGE, "--vary %s: value '%.*s' cannot name a folder", a->name,
                               (int)n, v);
        memcpy(a->value[a->n], v, n);
        a->value[a->n++][n] = '\0';
        v += n + (v[n] == ',');
    }
    return WS_OK;
}

static int parse_plan(int argc, char **argv, sweep_plan *p, int *help, ws_status *st) {
    memset(p, 0, sizeof *p);
    p->views = 6;
    p->cell = 128;
    *help = 0;
    p->fit_args = ws_calloc((size_t)argc + 1, sizeof *p->fit_args, "arguments", st);
    if (!p->fit_args) return st->code;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            *help = 1;
            return WS_OK;
        }
        int is_int = !strcmp(a, "--sheet-views") || !strcmp(a, "--sheet_views") ||
                     !strcmp(a, "--sheet-cell") || !strcmp(a, "--sheet_cell");
        if ((!strcmp(a, "--out") || !strcmp(a, "--vary") || is_int) && !next)
            return ws_fail(st, WS_EUSAGE, "%s: needs a value", a);
        if (!strcmp(a, "--out")) {
            p->out = argv[++i];
        } else if (!strcmp(a, "--vary")) {
            if (p->nvary == MAX_VARY) return ws_fail(st, WS_EUSAGE, "--vary: at most %d", MAX_VARY);
            if (parse_vary(argv[++i], &p->vary[p->nvary++], st)) return st->code;
        } else if (is_int) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            int *dest = strstr(a, "views") ? &p->views : &p->cell;
            if (*end || v < 1 || v > 1024)
                return ws_fail(st, WS_EUSAGE, "%s: '%s' is not in [1, 1024]", a, argv[i]);
            *dest = (int)v;
        } else if (!p->scene && strncmp(a, "--", 2)) {
            p->scene = a;
        } else {
            p->fit_args[p->nfit++] = argv[i];
        }
    }
    if (!p->scene) return ws_fail(st, WS_EUSAGE, "sweep: missing SCENE (see --help)");
    if (!p->out) return ws_fail(st, WS_EUSAGE, "--out: required (see --help)");
    if (!p->nvary) return ws_fail(st, WS_EUSAGE, "--vary: required (see --help)");
    return WS_OK;
}

/* Run k of the grid (the last axis varies fastest): its folder name and
 * each axis' value index. */
static void run_of(const sweep_plan *p, int k, int *index, char *name, size_t size) {
    for (int a = p->nvary - 1; a >= 0; a--) {
        index[a] = k % p->vary[a].n;
        k /= p->vary[a].n;
    }
    size_t n = 0;
    name[0] = '\0';
    for (int a = 0; a < p->nvary && n < size; a++)
        n += (size_t)snprintf(name + n, size - n, "%s%s=%s", a ? "," : "", p->vary[a].name,
                              p->vary[a].value[index[a]]);
}

static int exists(const char *path) { return access(path, F_OK) == 0; }

/* Runs `wiresketch fit ARGS` (this very program) and waits for it. */
static int spawn_fit(char **args, const char *run, ws_status *st) {
    char self[WS_PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) return ws_fail(st, WS_EIO, "sweep: cannot find the program itself: %s", strerror(errno));
    self[n] = '\0';
    args[0] = self;
    pid_t pid;
    int rc = posix_spawn(&pid, self, NULL, NULL, args, environ);
    if (rc) return ws_fail(st, WS_EIO, "%s: cannot start fit: %s", run, strerror(rc));
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return ws_fail(st, WS_EIO, "%s: lost the fit: %s", run, strerror(errno));
    /* 128 + N: the fit was stopped by signal N, checkpointed, and the sweep
     * stops with it (the same command continues) */
    if (WIFEXITED(status) && WEXITSTATUS(status) > 128) {
        if (!sweep_stop) sweep_stop = WEXITSTATUS(status) - 128;
        return WS_OK;
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status))
        return ws_fail(st, WIFEXITED(status) && WEXITSTATUS(status) == 2 ? WS_EUSAGE : WS_EINPUT,
                       "%s: the fit failed (exit %d; its message is above)", run,
                       WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return WS_OK;
}

/* The arguments after `fit` of run k when it starts anew: SCENE --out
 * DIR/RUN [fit options] --NAME VALUE ... (the varied values last). args
 * holds 2 MAX_VARY + nfit + 3 pointers; values and dir are its storage. */
static int new_run_args(const sweep_plan *p, const int *index, const char *dir, char **args,
                        char values[][80]) {
    int n = 0;
    args[n++] = (char *)p->scene;
    args[n++] = "--out";
    args[n++] = (char *)dir;
    for (int i = 0; i < p->nfit; i++) args[n++] = p->fit_args[i];
    for (int a = 0; a < p->nvary; a++) {
        snprintf(values[a], 80, "--%s", p->vary[a].name);
        args[n++] = values[a];
        args[n++] = (char *)p->vary[a].value[index[a]];
    }
    args[n] = NULL;
    return n;
}

/* Every run's arguments checked as `fit` would before the first starts, so
 * a bad value in the last run of a grid fails now, not hours later. */
static int check_runs(const sweep_plan *p, int nruns, ws_status *st) {
    char **args = ws_calloc((size_t)p->nfit + 2 * MAX_VARY + 4, sizeof *args, "arguments", st);
    if (!args) return st->code;
    for (int k = 0; k < nruns && !st->code; k++) {
        int index[MAX_VARY];
        char name[RUN_NAME_MAX], dir[WS_PATH_MAX], values[MAX_VARY][80];
        run_of(p, k, index, name, sizeof name);
        snprintf(dir, sizeof dir, "%s/%s", p->out, name);
        int n = new_run_args(p, index, dir, args, values);
        if (cmd_fit_check_arguments(n, args, st)) {
            char why[sizeof st->msg];
            snprintf(why, sizeof why, "%s", st->msg);
            ws_fail(st, st->code, "sweep: run %d of %d (%s): %s", k + 1, nruns, name, why);
        }
    }
    free(args);
    return st->code;
}

/* One run: skipped when done, resumed from its checkpoint, or started. */
static int do_run(const sweep_plan *p, int k, int nruns, ws_status *st) {
    int index[MAX_VARY];
    char name[RUN_NAME_MAX], dir[WS_PATH_MAX], path[WS_PATH_MAX + 32], values[MAX_VARY][80];
    run_of(p, k, index, name, sizeof name);
    snprintf(dir, sizeof dir, "%s/%s", p->out, name);
    snprintf(path, sizeof path, "%s/sweep.done", dir);
    if (exists(path)) {
        fprintf(stderr, "sweep: run %d of %d (%s): done before, skipped\n", k + 1, nruns, name);
        return WS_OK;
    }
    char **args = ws_calloc((size_t)p->nfit + 2 * MAX_VARY + 6, sizeof *args, "arguments", st);
    if (!args) return st->code;
    args[1] = "fit";
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    int resume = exists(path);
    if (resume) {
        args[2] = "--resume";
        args[3] = dir;
        args[4] = NULL;
    } else {
        new_run_args(p, index, dir, args + 2, values);
    }
    fprintf(stderr, "sweep: run %d of %d (%s)%s\n", k + 1, nruns, name, resume ? ": resumed" : "");
    int rc = spawn_fit(args, dir, st);
    free(args);
    if (rc || sweep_stop) return rc;
    snprintf(path, sizeof path, "%s/sweep.done", dir);
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "%s\n", name);
    return ws_outfile_commit(&f, st);
}

int cmd_sweep(int argc, char **argv) {
    ws_status st;
    ws_status_clear(&st);
    sweep_plan p;
    int help;
    if (parse_plan(argc, argv, &p, &help, &st)) {
        free(p.fit_args);
        return ws_cli_fail(&st);
    }
    if (help) {
        free(p.fit_args);
        return usage_help();
    }
    long nruns = 1;
    for (int a = 0; a < p.nvary; a++) nruns *= p.vary[a].n;
    char(*names)[RUN_NAME_MAX] = nruns > MAX_RUNS ? NULL : ws_malloc(sizeof *names * nruns, "run names", &st);
    const char **runs = names ? ws_malloc(sizeof *runs * nruns, "run names", &st) : NULL;
    for (int k = 0; runs && k < nruns; k++) {
        int index[MAX_VARY];
        run_of(&p, k, index, names[k], sizeof names[k]);
        runs[k] = names[k];
    }
    const ws_sweep_page page = {p.scene, p.out, (int)nruns, runs, p.views, p.cell};
    int rc = nruns > MAX_RUNS ? ws_fail(&st, WS_EUSAGE, "--vary: %ld runs; at most %d", nruns, MAX_RUNS)
             : !runs          ? st.code
                              : ws_sweep_page_check(&page, &st) || check_runs(&p, (int)nruns, &st);
    if (!rc && !(rc = ws_outfile_protect(NULL, 0, &p.scene, 1, &st))) rc = ws_mkdir(p.out, &st);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    static const int stops[] = {SIGINT, SIGTERM, SIGHUP, SIGXCPU, SIGXFSZ};
    for (size_t k = 0; k < sizeof stops / sizeof stops[0]; k++) sigaction(stops[k], &sa, NULL);
    for (int k = 0; k < nruns && !rc && !sweep_stop; k++) rc = do_run(&p, k, (int)nruns, &st);
    if (!rc && !sweep_stop) rc = ws_sweep_page_write(&page, &st);
    free(p.fit_args);
    free(names);
    free(runs);
    if (rc) return ws_cli_fail(&st);
    if (sweep_stop) {
        fprintf(stderr, "wiresketch: sweep stopped by signal %d; run the same command again to continue\n",
                (int)sweep_stop);
        return 128 + sweep_stop;
    }
    fprintf(stderr, "wiresketch: sweep done; see %s/index.html and %s/contact_sheet.png\n", p.out, p.out);
    return 0;
}
