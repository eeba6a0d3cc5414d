/* cmd_check.c: `wiresketch check SCENE`: whether every view's photo agrees
 * with its camera (geometry/check.h): a table per split (with each split's
 * agreement with the reference split's hull), then one line saying what is
 * wrong and how to fix it. Exit 0 when consistent, 1 not. Where the scene
 * has a gt_points.ply, also how much of the silhouettes it leaves
 * uncovered (geometry/gt_coverage.h) and, where it misses a part, a warning
 * line; that leaves the exit status alone, as the ground truth does not
 * enter a fit (docs/METHOD.md section 12). A scene with no usable
 * silhouette gets its line alone (exit 1). */
#include <math.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>
#include "cli/args.h"
#include "cli/cli_rows.h"
#include "cli/cli_gt.h"
#include "cli/cli_view.h"
#include "base/outfile.h"
#include "base/progress.h"
#include "cli/commands.h"
#include "geometry/check.h"
#include "io/scene_crops.h"
#include "metrics/quality.h"
#include "objective/view_targets.h"
#include "geometry/roi.h"

static void print_table(const ws_scene *scene, const ws_check_report *r) {
    char vs[16] = "vs -";
    if (r->reference >= 0) snprintf(vs, sizeof vs, "vs %s", ws_split_names[r->reference]);
    printf("%-6s %5s %6s %6s %6s %6s %8s  %s\n", "split", "views", "mean", "worst", "focal", "gain", vs,
           "views that disagree (agreement)");
    for (int s = 0; s < WS_NSPLITS; s++) {
        const ws_check_split *c = &r->split[s];
        if (c->n == 0) continue;
        printf("%-6s %5d %6.3f %6.3f ", ws_split_names[s], c->n, c->mean, c->worst);
        if (c->tight_fixed > 0) /* estimated (check.h) */
            printf("%6.3f %6.4f ", c->focal_estimate, c->tight_fixed - c->tight_mean);
        else
            printf("%6s %6s ", "-", "-");
        if (!isnan(c->cross)) /* measured against the reference (check.h) */
            printf("%8.3f  ", c->cross);
        else
            printf("%8s  ", "-");
        for (int d = 0; d < c->ndisagree && d < 12; d++)
            printf("%s%s (%.2f)", d ? ", " : "", scene->split[s].views[c->disagree[d]].name,
                   c->agreement[c->disagree[d]]);
        printf("%s\n", c->ndisagree > 12 ? ", ..." : c->ndisagree ? "" : "-");
    }
}

/* Where scene_dir has a ground-truth point cloud: the table of how much
 * of each view's silhouette it covers, then its verdict (a warning on
 * stderr where it misses a part; on stdout too unless both are one
 * terminal). */
static int print_coverage(const ws_scene *scene, ws_view_targets *targets, const char *scene_dir, int one_terminal,
                          ws_status *st) {
    char gt_points[WS_PATH_MAX], gt_curves[WS_PATH_MAX];
    ws_scene_ground_truth(scene_dir, gt_points, gt_curves);
    ws_gt_coverage cov;
    if (!gt_points[0]) return WS_OK;
    if (ws_scene_gt_coverage(scene, targets, gt_points, gt_curves, &cov, st)) return st->code;
    printf("\n");
    ws_cli_gt_coverage_table(stdout, scene, &cov);
    if (cov.flagged) {
        if (!one_terminal) printf("%s\n", cov.line);
        fprintf(stderr, "wiresketch: warning: %s\n", cov.line);
    } else {
        printf("%s: the ground truth covers the silhouettes\n", gt_points);
    }
    return WS_OK;
}

int cmd_check(int argc, char **argv) {
    const char *fixed_dir = NULL, *images = NULL, *masks = NULL;
    int size = 224, resolution = WS_CHECK_RESOLUTION;
    const ws_arg args[] = {
        WS_ROW_SIZE(&size),
        {"--resolution", WS_ARG_INT, &resolution, 0, "hull voxels along its longest side [64]"},
        WS_ROW_IMAGES(&images),
        WS_ROW_MASKS(&masks),
        {"--write-fixed", WS_ARG_STRING, &fixed_dir, 0,
         "write a corrected copy of the scene here when the cause is found [none]"},
    };
    const ws_command_spec spec = {
        "check SCENE [options]",
        "Check that every view's silhouette agrees with the visual hull of the other views of its split, and\n"
        "the views of the other splits with the hull of the split with the most views (column \"vs train\").",
        args, sizeof args / sizeof args[0], 1, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) return done;
    if (ws_cli_check_size(size, &st)) return ws_cli_fail(&st);
    if (resolution < 8 || resolution > 512) {
        ws_fail(&st, WS_EUSAGE, "--resolution: %d is not in [8, 512]", resolution);
        return ws_cli_fail(&st);
    }
    if (fixed_dir && (ws_outfile_protect(NULL, 0, pos, 1, &st) || ws_outfile_check(fixed_dir, &st)))
        return ws_cli_fail(&st);
    ws_scene scene = {0};
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = opt.height = size;
    opt.images_dir = images;
    opt.masks_dir = masks;
    ws_progress progress;
    ws_progress_init(&progress);
    opt.progress = &progress;
    ws_view_targets *targets = NULL;
    const ws_silhouette *sil[WS_NSPLITS];
    int rc = ws_roi_load_scene(&scene, pos[0], &opt, NULL, NULL, NULL, &st) || ws_view_targets_create(&targets, &scene, &st);
    for (int s = 0; s < WS_NSPLITS && !rc; s++) rc = ws_view_targets_silhouettes(targets, s, &sil[s], &st);
    ws_check_report r;
    if (rc || ws_check_scene(&scene, sil, resolution, &r, &st)) {
        ws_view_targets_free(targets);
        ws_scene_free(&scene);
        return ws_cli_fail(&st);
    }
    /* a line that is both the report's (stdout) and the failure's or the
     * warning's (stderr) is shown once when both are the same terminal */
    struct stat out_st, err_st;
    int one_terminal = isatty(1) && isatty(2) && fstat(1, &out_st) == 0 && fstat(2, &err_st) == 0 &&
                       out_st.st_rdev == err_st.st_rdev;
    char crops[1024];
    ws_scene_crop_line(&scene, crops, sizeof crops);
    if (crops[0]) printf("%s\n", crops);
    ws_scene_mask_line(&scene, crops, sizeof crops);
    if (crops[0]) printf("%s\n", crops);
    if (!r.no_silhouette) print_table(&scene, &r);
    int code = r.consistent ? 0 : 1;
    if (r.consistent) {
        printf("consistent: every view agrees with the others\n");
    } else {
        if (!one_terminal) printf("%s\n", r.line);
        fprintf(stderr, "wiresketch: %s\n", r.line);
    }
    if (!r.no_silhouette && print_coverage(&scene, targets, pos[0], one_terminal, &st)) /* it measures silhouettes */
        code = ws_cli_fail(&st);
    if (!r.consistent && fixed_dir) {
        if (ws_check_write_fixed(&scene, &r, fixed_dir, &st))
            code = ws_cli_fail(&st);
        else
            printf("wrote a corrected copy to %s\n", fixed_dir);
    }
    ws_check_report_free(&r);
    ws_view_targets_free(targets);
    ws_scene_free(&scene);
    return code;
}
