/* cmd_grad.c: `wiresketch grad`: the loss of one view and its gradient with
 * respect to every control point, as JSON on stdout (%.17g), for checking
 * the whole chain curves -> Gaussians -> splat -> loss against an
 * independent implementation (tools/reference_splat.py). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "args.h"
#include "cli_view.h"
#include "commands.h"
#include "curves.h"
#include "loss_l2.h"
#include "splat.h"

/* The losses --loss accepts; view_loss has one branch for each. */
static const char *const loss_names = "l2";

static int check_loss(const char *loss, ws_status *st) {
    if (strcmp(loss, "l2"))
        return ws_fail(st, WS_EUSAGE, "--loss: '%s' is not a loss (%s)", loss, loss_names);
    return WS_OK;
}

/* The loss of one view's stroke image alpha (H x W) and dL/dalpha
 * (overwritten). */
static int view_loss(const char *loss, const ws_view *view, const double *alpha, double *value,
                     double *dalpha, ws_status *st) {
    size_t pixels = (size_t)view->photo.width * view->photo.height;
    if (!strcmp(loss, "l2")) {
        *value = ws_loss_l2_forward(alpha, view->photo.data, pixels);
        memset(dalpha, 0, pixels * sizeof *dalpha);
        ws_loss_l2_backward(alpha, view->photo.data, pixels, 1.0, dalpha);
        return WS_OK;
    }
    return ws_fail(st, WS_EINTERNAL, "grad: loss '%s' has no implementation", loss);
}

/* Loss and dL/dP (curves->n x 4 x 3) of view `v`. */
static int view_gradient(const ws_curves *curves, const ws_view *v, const char *loss,
                         const ws_splat_options *opt, double *value, double *dP, ws_status *st) {
    ws_gaussians g = {0};
    ws_splat *splat = NULL;
    int W = v->cam.width, H = v->cam.height;
    double *alpha = ws_malloc((size_t)W * H * 2 * sizeof *alpha, "the stroke image", st);
    double *dalpha = alpha + (size_t)W * H, *dmu = NULL;
    if (alpha && !ws_curves_sample(curves, &g, st) &&
        (dmu = ws_malloc((size_t)g.n * 3 * sizeof *dmu, "Gaussian gradients", st)) &&
        !ws_splat_create(&splat, W, H, st) &&
        !ws_splat_forward(splat, &v->cam, g.mu, g.n, curves->thickness, opt, alpha, st) &&
        !view_loss(loss, v, alpha, value, dalpha, st) &&
        !ws_splat_backward(splat, dalpha, dmu, st))
        ws_curves_backward(curves, &g, dmu, dP);
    free(dmu);
    free(alpha);
    ws_splat_free(splat);
    ws_gaussians_free(&g);
    return st->code;
}

static void print_gradient(double value, const double *dP, int n) {
    printf("{\"loss\": %.17g, \"grad\": [", value);
    for (int c = 0; c < n; c++) {
        printf("%s\n  [", c ? "," : "");
        for (int j = 0; j < 4; j++) {
            const double *d = dP + (size_t)c * 12 + j * 3;
            printf("%s[%.17g, %.17g, %.17g]", j ? ", " : "", d[0], d[1], d[2]);
        }
        printf("]");
    }
    printf("%s]}\n", n ? "\n" : "");
}

int cmd_grad(int argc, char **argv) {
    const char *curves_path = NULL, *split_name = "test", *loss = "l2";
    int view = 0, size = 224;
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    const ws_arg args[] = {
        {"--curves", WS_ARG_STRING, &curves_path, 0, "curve file [required]"},
        {"--split", WS_ARG_STRING, &split_name, 0, "train, val or test [test]"},
        {"--view", WS_ARG_INT, &view, 0, "view index within the split [0]"},
        {"--loss", WS_ARG_STRING, &loss, 0, "l2: mean squared difference with the photo [l2]"},
        {"--cutoff", WS_ARG_CUTOFF, &opt.cutoff, 0, "Gaussian cut-off radius in sigmas [4]"},
        {"--size", WS_ARG_INT, &size, 0, "working resolution in pixels, square [224]"},
    };
    const ws_command_spec spec = {
        "grad SCENE --curves C.json [options]",
        "Print the loss of one view and its gradient for every control point as JSON.",
        args, sizeof args / sizeof args[0], 1, 1};
    const char *pos[1];
    int npos, help;
    ws_status st;
    ws_status_clear(&st);
    if (ws_args_parse(&spec, argc, argv, pos, &npos, &help, &st)) return ws_cli_fail(&st);
    if (help) return 0;
    if (ws_cli_require(curves_path, "--curves", &st) || check_loss(loss, &st))
        return ws_cli_fail(&st);
    ws_curves curves = {0};
    ws_scene scene = {0};
    int split;
    double value = 0, *dP = NULL;
    if (!ws_curves_load(curves_path, &curves, &st) &&
        !ws_cli_load_split(pos[0], size, 1, split_name, &scene, &split, &st)) {
        if (!ws_cli_check_view(&scene, split, view, &st) &&
            (dP = ws_malloc((size_t)curves.n * 12 * sizeof *dP, "control point gradients", &st)) &&
            !view_gradient(&curves, &scene.split[split].views[view], loss, &opt, &value, dP, &st))
            print_gradient(value, dP, curves.n);
        ws_scene_free(&scene);
    }
    free(dP);
    ws_curves_free(&curves);
    return st.code ? ws_cli_fail(&st) : 0;
}
