/* cli_gt.h: the ground-truth coverage (geometry/gt_coverage.h) as `check`
 * and `eval` show it: measured from a scene file's silhouettes, printed as
 * table rows or as a JSON field. */
#ifndef WS_CLI_GT_H
#define WS_CLI_GT_H
#include <stdio.h>
#include "geometry/gt_coverage.h"
#include "objective/view_targets.h"

/* Reads gt_points (a PLY path) and measures its coverage of the
 * silhouettes of every split of scene (loaded with its images; targets
 * made from it). gt_curves: the scene's ground-truth curves, NULL or ""
 * for none; where given, its points are the axes of tubes of radius its
 * thickness (synth/synth.h), which each disc grows by. */
int ws_cli_gt_coverage(const ws_scene *scene, ws_view_targets *targets, const char *gt_points,
                       const char *gt_curves, ws_gt_coverage *c, ws_status *st);

/* One row per split: views, mean and worst uncovered fraction, the worst
 * view; then the point spacing and the voxels uncovered in most views. */
void ws_cli_gt_coverage_table(FILE *fp, const ws_scene *scene, const ws_gt_coverage *c);

/* `"gt_coverage": {...}` (no separator before it). */
void ws_cli_gt_coverage_json(FILE *fp, const ws_gt_coverage *c);

#endif
