/* cli_gt.h: the ground-truth coverage (objective/scene_gt_coverage.h) as
 * `check` shows it: table rows. */
#ifndef WS_CLI_GT_H
#define WS_CLI_GT_H
#include <stdio.h>
#include "objective/scene_gt_coverage.h"

/* One row per split: views, mean and worst uncovered fraction, the worst
 * view; then the point spacing and the voxels uncovered in most views. */
void ws_cli_gt_coverage_table(FILE *fp, const ws_scene *scene, const ws_gt_coverage *c);

#endif
