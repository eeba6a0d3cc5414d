/* cmd_grad.c: `wiresketch grad`: the loss of one view and its gradient with
 * respect to every control point, as JSON on stdout (%.17g), for checking
 * the whole chain curves -> Gaussians -> splat -> loss (l2, edges, or CLIP:
 * item 0 only, no augmentation) against an independent implementation
 * (tools/reference_splat.py, tools/reference_clip_grad.py). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/json_number.h"
#include "cli/args.h"
#include "cli/cli_rows.h"
#include "cli/cli_loss.h"
#include "cli/cli_view.h"
#include "cli/commands.h"
#include "objective/objective.h"
#include "base/runtime.h"

/* Loss and dL/dP (curves->n x 4 x 3) of view `view` of `split`. */
static int view_gradient(const ws_curves *curves, const ws_scene *scene, int split, int view,
                         const ws_loss_options *lo, const ws_splat_options *so, double *value,
                         double *dP, ws_status *st) {
    ws_objective *obj = NULL;
    memset(dP, 0, (size_t)curves->n * WS_CURVE_FLOATS * sizeof *dP);
    if (!ws_objective_create(&obj, scene, lo, so, curves->n, st))
        ws_objective_view(obj, curves, split, view, 0, NULL, 1.0, value, dP, st);
    ws_objective_free(obj);
    return st->code;
}

static void print_gradient(double value, const double *dP, int n) {
    putchar('{');
    ws_json_number(stdout, "loss", value, 17);
    printf(", \"grad\": [");
    int bad = 0;
    for (int c = 0; c < n; c++) {
        printf("%s\n  [", c ? "," : "");
        for (int j = 0; j < 4; j++) {
            const double *d = dP + (size_t)c * WS_CURVE_FLOATS + j * 3;
            for (int a = 0; a < 3; a++) {
                fputs(a ? ", " : j ? ", [" : "[", stdout);
                bad += ws_json_value(stdout, d[a], 17);
            }
            putchar(']');
        }
        printf("]");
    }
    printf("%s]", n ? "\n" : "");
    if (bad) printf(", \"grad_why\": \"%d of its values are not finite, which JSON cannot hold\"", bad);
    printf("}\n");
}

int cmd_grad(int argc, char **argv) {
    const char *curves_path = NULL, *split_name = "test", *loss_name = "auto", *background = "black";
    const char *geometric = "blocks", *hidden = NULL;
    int view = 0, size = 224, threads = 0;
    double edges_weight = 1.0;
    ws_arg_list layers = {0};
    ws_splat_options so;
    ws_splat_options_default(&so);
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    const ws_arg args[] = {
        WS_ROW_CURVES(&curves_path),
        WS_ROW_SPLIT(&split_name),
        WS_ROW_BACKGROUND(&background),
        WS_ROW_VIEW(&view),
        WS_ROW_LOSS(&loss_name),
        WS_ROW_WEIGHTS(&lo.weights_path),
        WS_ROW_CONV_WEIGHT(&lo.conv_weight),
        WS_ROW_LAYER_WEIGHTS(&layers),
        WS_ROW_GEOMETRIC(&geometric),
        WS_ROW_HIDDEN(&hidden),
        WS_ROW_FC_WEIGHT(&lo.fc_weight),
        WS_ROW_EDGES_WEIGHT(&edges_weight),
        WS_ROW_CUTOFF(&so.cutoff),
        WS_ROW_SIZE(&size),
        WS_ROW_THREADS(&threads),
    };
    const ws_command_spec spec = {
        "grad SCENE --curves C.json [options]",
        "Print the loss of one view and its gradient for every control point as JSON\n"
        "(item 0 only: no augmentation, so CLIP's global term is absent).",
        args, sizeof args / sizeof args[0], 1, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) return done;
    lo.global_weight = 0; /* it compares augmented items only */
    if (ws_cli_require(curves_path, "--curves", &st) ||
        ws_cli_choose_loss(ws_cli_auto_loss(loss_name, lo.weights_path), edges_weight, &layers, geometric, hidden, &lo, &st) ||
        ws_runtime_init(threads, &st))
        return ws_cli_fail(&st);
    ws_cli_announce_loss(loss_name, lo.weights_path);
    ws_curves curves = {0};
    ws_scene scene = {0};
    int split;
    double value = 0, *dP = NULL;
    if (!ws_curves_load(curves_path, &curves, &st) &&
        !ws_cli_load_split(pos[0], size, 1, background, split_name, &scene, &split, &st)) {
        if (!ws_cli_check_view(&scene, split, view, &st) &&
            (dP = ws_malloc((size_t)curves.n * WS_CURVE_FLOATS * sizeof *dP, "control point gradients",
                            &st)) &&
            !view_gradient(&curves, &scene, split, view, &lo, &so, &value, dP, &st))
            print_gradient(value, dP, curves.n);
        ws_scene_free(&scene);
    }
    free(dP);
    ws_curves_free(&curves);
    return st.code ? ws_cli_fail(&st) : 0;
}
