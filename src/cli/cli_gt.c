/* cli_gt.c: the ground-truth coverage as `check` shows it (cli_gt.h). */
#include "cli/cli_gt.h"

void ws_cli_gt_coverage_table(FILE *fp, const ws_scene *scene, const ws_gt_coverage *c) {
    fprintf(fp, "%-6s %5s %9s %9s  %s\n", "split", "views", "uncovered", "worst", "ground truth: worst view");
    for (int s = 0; s < WS_NSPLITS; s++) {
        const ws_gt_coverage_split *g = &c->split[s];
        if (g->n == 0) continue;
        fprintf(fp, "%-6s %5d %9.4f %9.4f  %s\n", ws_split_names[s], g->n, g->mean, g->worst,
                scene->split[s].views[g->worst_view].name);
    }
    if (c->reference >= 0)
        fprintf(fp, "ground truth: point spacing %.4g, %ld voxels of the %s hull uncovered in most views\n",
                c->spacing, c->region_voxels, ws_split_names[c->reference]);
}
