/* cmd_rank.c: `wiresketch rank SCENE`: the losses of the ground truth and
 * of the sketches an objective must rank below it (ranking.h), as a
 * markdown table, one column per thickness. */
#include <stdio.h>
#include <string.h>
#include "base/paths.h"
#include "base/runtime.h"
#include "cli/args.h"
#include "cli/cli_rows.h"
#include "cli/cli_loss.h"
#include "cli/cli_view.h"
#include "cli/commands.h"
#include "objective/ranking.h"
#include "geometry/roi.h"

int cmd_rank(int argc, char **argv) {
    const char *split_name = "test", *loss_name = "auto", *gt_path = NULL, *edge_maps = NULL;
    const char *geometric = "blocks", *hidden_name = NULL;
    int size = 224, threads = 0;
    ws_arg_list thick = {4, {0.005, 0.01, 0.02, 0.04}};
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    const ws_arg args[] = {
        WS_ROW_LOSS(&loss_name),
        WS_ROW_WEIGHTS(&lo.weights_path),
        WS_ROW_GEOMETRIC(&geometric),
        WS_ROW_HIDDEN(&hidden_name),
        WS_ROW_GT_CURVES(&gt_path),
        {"--thickness", WS_ARG_DOUBLES, &thick, 16, "thicknesses, one column each [0.005 0.01 0.02 0.04]"},
        WS_ROW_SPLIT(&split_name),
        WS_ROW_EDGE_MAPS(&edge_maps),
        WS_ROW_SIZE(&size),
        WS_ROW_THREADS(&threads),
    };
    ws_command_spec spec = {"rank SCENE [options]",
                            "the losses of the ground truth and of worse sketches (empty, a dot, dots,\n"
                            "half, shifted by 1% and 5%, plus 10 random strokes), one column per thickness",
                            args, (int)(sizeof args / sizeof args[0]), 1, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) return done;
    int split = ws_split_index(split_name);
    if (split < 0) ws_fail(&st, WS_EUSAGE, "--split: '%s' is not train, val or test", split_name);
    for (int k = 0; k < thick.n && !st.code; k++)
        if (!(thick.v[k] > 0)) ws_fail(&st, WS_EUSAGE, "--thickness: %g is not positive", thick.v[k]);
    const char *given_loss = loss_name;
    loss_name = ws_cli_auto_loss(loss_name, lo.weights_path);
    if (st.code || ws_cli_check_size(size, &st) ||
        ws_cli_choose_loss(loss_name, 1.0, NULL, geometric, hidden_name, &lo, &st) ||
        ws_runtime_init(threads, &st))
        return ws_cli_fail(&st);
    char gt_default[WS_PATH_MAX];
    snprintf(gt_default, sizeof gt_default, "%s/gt_curves.json", pos[0]);
    ws_scene scene = {0};
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = size;
    so.edge_maps_dir = edge_maps;
    ws_curves gt = {0};
    ws_splat_options splat;
    ws_splat_options_default(&splat);
    ws_objective *obj = NULL;
    double table[16][WS_RANK_COUNT];
    int rc = ws_curves_load(gt_path ? gt_path : gt_default, &gt, &st);
    if (!rc) rc = ws_roi_load_scene(&scene, pos[0], &so, NULL, NULL, NULL, &st);
    if (!rc) rc = ws_objective_create(&obj, &scene, &lo, &splat, ws_rank_curves(&gt), &st);
    for (int k = 0; k < thick.n && !rc; k++) rc = ws_rank_losses(obj, split, &gt, thick.v[k], 0, table[k], &st);
    if (!rc) {
        ws_cli_announce_loss(given_loss, lo.weights_path);
        printf("| %s loss, %s (%d views, %d px) |", loss_name, pos[0], scene.split[split].n, size);
        for (int k = 0; k < thick.n; k++) printf(" %g |", thick.v[k]);
        printf("\n| --- |");
        for (int k = 0; k < thick.n; k++) printf(" ---: |");
        printf("\n");
        for (int r = 0; r < WS_RANK_COUNT; r++) {
            printf("| %s |", ws_rank_names[r]);
            for (int k = 0; k < thick.n; k++) {
                int beaten = r > WS_RANK_TRUTH && table[k][r] <= table[k][WS_RANK_TRUTH];
                printf(" %s%.4g%s |", beaten ? "**" : "", table[k][r], beaten ? "**" : "");
            }
            printf("\n");
        }
    }
    ws_objective_free(obj);
    ws_scene_free(&scene);
    ws_curves_free(&gt);
    return rc ? ws_cli_fail(&st) : 0;
}
