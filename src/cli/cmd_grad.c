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
        {"--curves", WS_ARG_STRING, &curves_path, 0, "curve file [required]"},
        {"--split", WS_ARG_STRING, &split_name, 0, "train, val or test [test]"},
        {"--background", WS_ARG_STRING, &background, 0, WS_CLI_BACKGROUND_HELP},
        {"--view", WS_ARG_INT, &view, 0, "view index within the split [0]"},
        {"--loss", WS_ARG_STRING, &loss_name, 0, WS_CLI_LOSS_HELP("l2, edges, clip or clip+edges")},
        {"--weights", WS_ARG_STRING, &lo.weights_path, 0, "CLIP weight file [weights/clip-vit-b32.bin]"},
        {"--clip-conv-loss", WS_ARG_DOUBLE, &lo.conv_weight, 0, "geometric term weight [1]"},
        {"--clip-conv-layer-weights", WS_ARG_DOUBLES, &layers, WS_LOSS_MAX_LAYERS,
         "weight of block 0, 1, ... [0 0 1 1 0]"},
        {"--clip-geometric", WS_ARG_STRING, &geometric, 0, WS_CLI_GEOMETRIC_HELP},
        {"--hidden-lines", WS_ARG_STRING, &hidden, 0, WS_CLI_HIDDEN_HELP},
        {"--clip-fc-loss-weight", WS_ARG_DOUBLE, &lo.fc_weight, 0, "fc term weight [0.1]"},
        {"--edges-weight", WS_ARG_DOUBLE, &edges_weight, 0, "weight of the edge loss [1]"},
        {"--cutoff", WS_ARG_CUTOFF, &so.cutoff, 0, "Gaussian cut-off radius in sigmas [4]"},
        {"--size", WS_ARG_INT, &size, 0, "working resolution in pixels, square; the model's with CLIP [224]"},
        {"--threads", WS_ARG_INT, &threads, 0, "threads, 0 = one per core [0]"},
    };
    const ws_command_spec spec = {
        "grad SCENE --curves C.json [options]",
        "Print the loss of one view and its gradient for every control point as JSON\n"
        "(item 0 only: no augmentation, so CLIP's global term is absent).",
        args, sizeof args / sizeof args[0], 1, 1};
    const char *pos[1];
    int npos, help;
    ws_status st;
    ws_status_clear(&st);
    if (ws_args_parse(&spec, argc, argv, pos, &npos, &help, &st)) return ws_cli_fail(&st);
    if (help) return 0;
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
