/* test_fit_settings.c: report.html's settings table shows every option of
 * `fit` (each option `fit --help` lists, but --resume) with the value the
 * run used: given values as given, defaults as defaults, and the same
 * table after --resume. A short edge-loss fit of the committed fixture;
 * then the schedule a loss takes when --epochs and --inner-steps are left
 * unset, and the epochs --epochs auto gives a scene of n train views. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "fit/fit_options.h"
#include "test_util.h"

static const char *bin, *tmp;
static char report[1 << 20];

static void read_report(const char *dir) {
    char path[600];
    snprintf(path, sizeof path, "%s/report.html", dir);
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(report, 1, sizeof report - 1, f) : 0;
    if (f) fclose(f);
    report[n] = '\0';
}

/* The row of option `name` holds `value`. */
static int has_row(const char *name, const char *value) {
    char row[1024];
    snprintf(row, sizeof row, "<tr><th>%s</th><td>%s</td></tr>", name, value);
    return strstr(report, row) != NULL;
}

static int has_name(const char *name) {
    char row[600];
    snprintf(row, sizeof row, "<tr><th>%s</th><td>", name);
    return strstr(report, row) != NULL;
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("fit_settings");
    static char out[1 << 16];
    char run_dir[300];
    snprintf(run_dir, sizeof run_dir, "%s/run", tmp);
    /* the kernels a user chose are kept and recorded (runtime.h) */
    int rc = run_cmd(out, sizeof out,
                     "OPENBLAS_CORETYPE=Haswell %s fit tests/fixtures/scene_small --out %s/run --loss edges --size 64 --max-steps 2 "
                     "--radius 0.7 --length 0.05 --epochs 3 --inner-steps 2 --n-curves 7 --thickness 0.03 "
                     "--learning-rate 0.0125 --cutoff inf --seed 9 --threads 1 --quiet",
                     bin, tmp);
    CHECK(rc == 0, "fit: %s", out);
    read_report(run_dir);
    static const char *const given[][2] = {
        {"loss", "edges"},    {"size", "64"},         {"max-steps", "2"},      {"radius", "0.7"},
        {"length", "0.05"},   {"epochs", "3"},        {"inner-steps", "2"},    {"n-curves", "7"},
        {"thickness", "0.03"}, {"learning-rate", "0.0125"}, {"cutoff", "inf"}, {"seed", "9"},
        {"quiet", "yes"},     {"overlap", "0.6"},     {"batch-size", "1"},     {"eval-every", "60"},
        {"clip-conv-layer-weights", "0 0 1 1 0"},     {"init", "hull"},
    };
    for (size_t k = 0; k < sizeof given / sizeof given[0]; k++)
        CHECK(has_row(given[k][0], given[k][1]), "settings row %s = '%s'", given[k][0], given[k][1]);
    CHECK(strstr(report, "<tr><th>BLAS kernels</th><td>Haswell (OPENBLAS_CORETYPE=Haswell set in the environment: "
                         "kept") != NULL,
          "no settings row says which BLAS kernels ran");
    /* every option of --help has its row but those that say what the
     * invocation does (--resume, --config, --overwrite) */
    rc = run_cmd(out, sizeof out, "%s fit --help", bin);
    int options = 0, rows = 0;
    for (char *line = strtok(out, "\n"); line; line = strtok(NULL, "\n")) {
        char name[128];
        if (sscanf(line, "  --%127s", name) != 1 || !strcmp(name, "resume") || !strcmp(name, "config") ||
            !strcmp(name, "overwrite"))
            continue;
        options++;
        rows += has_name(name);
        CHECK(has_name(name), "no settings row for --%s", name);
    }
    CHECK(options >= 25 && rows == options, "%d of %d options in the table", rows, options);
    /* a resumed run with an override shows it */
    rc = run_cmd(out, sizeof out, "%s fit --resume %s/run --max-steps 3 --quiet", bin, tmp);
    CHECK(rc == 0, "resume: %s", out);
    read_report(run_dir);
    CHECK(has_row("max-steps", "3") && has_row("radius", "0.7"), "resumed table: stored and overridden");
    /* --epochs auto: 24 up to 96 train views, then about 24 x 96 views'
     * steps (rounded up), never 0; a number is kept whatever the views */
    ws_fit_options opt;
    ws_fit_options_default(&opt);
    opt.epochs = WS_FIT_EPOCHS_AUTO;
    static const int views[][2] = {{1, 24}, {6, 24}, {96, 24}, {97, 24}, {100, 24}, {192, 12},
                                   {193, 12}, {200, 12}, {320, 8}, {2304, 1}, {100000, 1}};
    for (size_t k = 0; k < sizeof views / sizeof views[0]; k++)
        CHECK(ws_fit_epochs(&opt, views[k][0]) == views[k][1], "auto, %d views: %d epochs, not %d", views[k][0],
              ws_fit_epochs(&opt, views[k][0]), views[k][1]);
    opt.epochs = 24;
    CHECK(ws_fit_epochs(&opt, 200) == 24 && (opt.epochs = 0, ws_fit_epochs(&opt, 200)) == 0,
          "--epochs 24 and 0 kept with 200 views");
    /* left unset, the line loss takes 5 steps per view over 24 epochs (30
     * steps on one view fit its own errors: docs/RESULTS.md, "Where it stands
     * now"; auto: fewer past 96 views), validated every 60 batches, another
     * loss the original's 30 over 10, every 10 */
    static const char *const loss_defaults[][4] = {{"edges", "auto", "5", "60"}, {"l2", "10", "30", "10"}};
    for (int k = 0; k < 2; k++) {
        rc = run_cmd(out, sizeof out,
                     "%s fit tests/fixtures/scene_small --out %s/unset --loss %s --size 64 --max-steps 1 "
                     "--threads 1 --quiet --overwrite",
                     bin, tmp, loss_defaults[k][0]);
        CHECK(rc == 0, "fit --loss %s: %s", loss_defaults[k][0], out);
        snprintf(run_dir, sizeof run_dir, "%s/unset", tmp);
        read_report(run_dir);
        CHECK(has_row("epochs", loss_defaults[k][1]) && has_row("inner-steps", loss_defaults[k][2]) &&
                  has_row("eval-every", loss_defaults[k][3]),
              "--loss %s: epochs %s, inner-steps %s, eval-every %s", loss_defaults[k][0], loss_defaults[k][1],
              loss_defaults[k][2], loss_defaults[k][3]);
    }
    return check_summary();
}
