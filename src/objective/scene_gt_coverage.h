/* scene_gt_coverage.h: the ground-truth coverage (geometry/gt_coverage.h)
 * of a scene's ground-truth files, as `check`, `eval` and the fit's
 * outputs measure and write it. */
#ifndef WS_SCENE_GT_COVERAGE_H
#define WS_SCENE_GT_COVERAGE_H
#include <stdio.h>
#include "geometry/gt_coverage.h"
#include "objective/view_targets.h"

/* Reads gt_points (a PLY path) and measures its coverage of the
 * silhouettes of every split of scene (loaded with its images; targets
 * made from it). gt_curves: the scene's ground-truth curves, NULL or ""
 * for none; where given, its points are the axes of tubes of radius its
 * thickness (synth/synth.h), which each disc grows by. Where the train
 * views have no usable silhouette (geometry/check.h), nothing is measured:
 * c is all 0 (not flagged, reference -1). */
int ws_scene_gt_coverage(const ws_scene *scene, ws_view_targets *targets, const char *gt_points,
                         const char *gt_curves, ws_gt_coverage *c, ws_status *st);

/* `"gt_coverage": {...}` (no separator before it); with the flag's line as
 * "warning" when flagged. */
void ws_gt_coverage_json(FILE *fp, const ws_gt_coverage *c);

#endif
