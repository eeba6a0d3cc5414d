/* cmd_eval.c: `wiresketch eval SCENE --curves C.json`: the test loss of a
 * sketch (item 0, no augmentation) and its distance to the ground truth
 * (METHOD.md section 8), as one JSON object on stdout; with a ground-truth
 * point cloud also how much of the photos' silhouettes it leaves uncovered
 * (geometry/gt_coverage.h, field gt_coverage), and where it misses a part
 * the check's line as a warning on stderr; with reference lines
 * (SCENE/lines/SPLIT) the drawing score (metrics/drawing_score.h) of the
 * drawing a user gets (field drawing: the curves beside the hull's
 * outline, objective/line_evidence.h) and of the curves alone (field
 * drawing_curves). The loss's line targets are the fit's (fit/init.h):
 * where the train views have no usable silhouette, or with --bbox, the
 * edges the views agree on in the region of interest. The loss is computed
 * only when asked for (--loss NAME) or, by default, when it can be: the
 * CLIP loss when the CLIP weight file exists; distances need no weights. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/json_number.h"
#include "base/paths.h"
#include "base/progress.h"
#include "cli/args.h"
#include "cli/cli_gt.h"
#include "cli/cli_loss.h"
#include "cli/cli_rows.h"
#include "cli/cli_view.h"
#include "cli/commands.h"
#include "fit/init.h"
#include "io/pointcloud.h"
#include "metrics/drawing_score.h"
#include "objective/line_evidence.h"
#include "metrics/quality.h"
#include "objective/objective.h"
#include "base/runtime.h"

static void print_number(const char *key, double v) {
    fputs(", ", stdout);
    ws_json_number(stdout, key, v, 9);
}

/* *per (n_curves, allocated): where the surface distance of the Gaussians
 * g of the n_curves curves comes from (ws_surface_curve). */
static int surface_by_curve(const char *gt_points, const ws_gaussians *g, int n_curves, ws_surface_curve **per,
                            ws_status *st) {
    ws_pointcloud pc = {0};
    ws_surface_gt gt = {0};
    *per = ws_malloc((size_t)(n_curves ? n_curves : 1) * sizeof **per, "per-curve distances", st);
    int rc = *per ? ws_pointcloud_load_ply(gt_points, &pc, st) : st->code;
    if (!rc) rc = ws_surface_gt_init(&gt, &pc, st);
    if (!rc) rc = ws_surface_distance_by_curve(&gt, g, n_curves, *per, st);
    ws_surface_gt_free(&gt);
    ws_pointcloud_free(&pc);
    return rc;
}

/* What eval measured, its one JSON object; NULL for what it did not. */
typedef struct {
    const char *split_name;
    int views, curves, gaussians;
    const char *loss_kind; /* NULL: no loss */
    double loss;
    const ws_quality *q;
    const ws_surface_curve *per; /* per curve (--per-curve) */
    const ws_drawing_score *drawing, *drawing_curves;
    const ws_gt_coverage *cov;
} eval_result;

static void print_result(const eval_result *r) {
    const ws_quality *q = r->q;
    printf("{\"split\": \"%s\", \"views\": %d, \"curves\": %d, \"gaussians\": %d, "
           "\"loss_kind\": \"%s\"",
           r->split_name, r->views, r->curves, r->gaussians, r->loss_kind ? r->loss_kind : "none");
    if (r->loss_kind) print_number("loss", r->loss);
    if (q->have_surface) {
        print_number("surface_mean", q->surface.mean);
        print_number("surface_p90", q->surface.p90);
        print_number("surface_precision", q->surface_strays.precision);
        printf(", \"surface_stray_curves\": %d", q->surface_strays.stray_curves);
        if (r->per) {
            printf(", \"surface_curves\": [");
            for (int ci = 0; ci < r->curves; ci++) {
                printf("%s{\"gaussians\": %d", ci ? ", " : "", r->per[ci].n);
                print_number("mean", r->per[ci].mean);
                print_number("adds", r->per[ci].adds);
                printf(", \"beyond_p90\": %d}", r->per[ci].beyond_p90);
            }
            printf("]");
        }
    }
    if (q->have_curves) {
        print_number("chamfer", q->curves.chamfer);
        print_number("precision", q->curves.precision);
        print_number("recall", q->curves.recall);
        print_number("fscore", q->curves.fscore);
        print_number("gaussian_precision", q->curve_strays.precision);
        printf(", \"stray_curves\": %d", q->curve_strays.stray_curves);
        printf(", ");
        ws_line_metrics_json(stdout, &q->lines);
    }
    if (r->drawing) {
        printf(", ");
        ws_drawing_score_json(stdout, "drawing", r->drawing);
        printf(", ");
        ws_drawing_score_json(stdout, "drawing_curves", r->drawing_curves);
    }
    if (r->cov) {
        printf(", ");
        ws_gt_coverage_json(stdout, r->cov);
    }
    printf("}\n");
}

/* The drawing scores of the curves against split `split`'s reference
 * lines in lines_dir: *drawing that of the drawing a user gets, the curves
 * beside the hull's outline (the curves alone, with a warning, where the
 * silhouettes carve no hull), *alone that of the curves alone. */
static int score_drawings(const ws_scene *scene, int split, const ws_curves *curves, const char *curves_path,
                          const char *lines_dir, ws_drawing_score *drawing, ws_drawing_score *alone, ws_status *st) {
    if (curves->n == 0)
        return ws_fail(st, WS_EINPUT, "%s: no curves to score against the reference lines", curves_path);
    ws_drawing_hull dh;
    int rc = ws_drawing_hull_make(&dh, scene, st), have_hull = rc == WS_OK;
    if (rc == WS_EINPUT) {
        fprintf(stderr, "wiresketch: warning: %s; the drawing is the curves alone\n", st->msg);
        ws_status_clear(st);
        rc = WS_OK;
    }
    if (!rc)
        rc = ws_drawing_score_split(&scene->split[split], scene->width, scene->height, curves, lines_dir, NULL, NULL,
                                    alone, st);
    if (!rc)
        rc = ws_drawing_score_split(&scene->split[split], scene->width, scene->height, curves, lines_dir,
                                    have_hull ? ws_drawing_hull_render : NULL, &dh, drawing, st);
    if (have_hull) ws_drawing_hull_free(&dh);
    return rc;
}

/* The loss's view targets, made as the fit makes them: where the train
 * views have no usable silhouette (or with --bbox), the edges the views agree
 * on in the region of interest (fit/init.h), whose line goes to stderr
 * (stdout is the JSON); else the photos' own, as the loss would make them. */
static int loss_targets(const ws_roi *roi, const ws_status *roi_st, const ws_scene *scene, ws_view_targets **targets,
                        ws_edge_consensus *c, ws_status *st) {
    char line[WS_CHECK_LINE];
    if (ws_view_targets_create(targets, scene, st) || ws_fit_consensus(roi, roi_st, scene, *targets, c, line, st))
        return st->code;
    if (line[0]) fprintf(stderr, "%s\n", line);
    return WS_OK;
}

/* lo NULL: no loss (the scene's cameras only are read). */
static int evaluate_sketch(const char *scene_dir, const char *curves_path, const char *split_name,
                           const ws_scene_options *scene_opt, const char *loss_name, const char *bbox,
                           const ws_loss_options *lo,
                           const ws_splat_options *so, const char *gt_points, const char *gt_curves,
                           int per_curve, ws_status *st) {
    int split = ws_split_index(split_name);
    if (split < 0) return ws_fail(st, WS_EUSAGE, "--split: '%s' is not train, val or test", split_name);
    ws_scene scene = {0}, photos = {0}; /* photos: the scene with its images, for the coverage */
    ws_scene_options sopt = *scene_opt;
    int coverage = gt_points && *gt_points;
    char lines_dir[WS_PATH_MAX];
    int have_lines = ws_drawing_lines_dir(scene_dir, split_name, lines_dir);
    sopt.load_images = lo != NULL || have_lines; /* a drawing's hull needs the photos */
    ws_curves curves = {0};
    ws_gaussians g = {0};
    ws_objective *obj = NULL;
    ws_view_targets *targets = NULL, *line_targets = NULL; /* the coverage's, the loss's */
    ws_edge_consensus consensus = {0};
    ws_loss_options with_targets = lo ? *lo : (ws_loss_options){0};
    ws_gt_coverage cov;
    double mean = NAN;
    ws_quality q;
    int rc = ws_curves_load(curves_path, &curves, st);
    if (!rc && curves.n == 0 && ((gt_points && *gt_points) || (gt_curves && *gt_curves)))
        rc = ws_fail(st, WS_EINPUT, "%s: no curves to measure against the ground truth", curves_path);
    double box[6];
    ws_roi roi;
    ws_status roi_st;
    if (!rc && bbox) rc = ws_roi_parse_bbox(bbox, box, st);
    if (!rc) rc = ws_roi_load_scene(&scene, scene_dir, &sopt, bbox ? box : NULL, &roi, &roi_st, st);
    char masks_line[1024]; /* stdout is the JSON */
    if (!rc) ws_scene_mask_line(&scene, masks_line, sizeof masks_line);
    if (!rc && masks_line[0]) fprintf(stderr, "%s\n", masks_line);
    if (!rc) rc = ws_curves_sample(&curves, &g, st);
    if (!rc && lo) rc = loss_targets(&roi, &roi_st, &scene, &line_targets, &consensus, st);
    with_targets.targets = line_targets;
    if (!rc && lo) rc = ws_objective_create(&obj, &scene, &with_targets, so, curves.n, st);
    if (!rc && lo) rc = ws_objective_split_mean(obj, &curves, split, NULL, &mean, st);
    if (!rc) rc = ws_quality_measure(&curves, gt_points, gt_curves, &q, st);
    ws_drawing_score drawing, drawing_curves;
    char why[WS_PATH_MAX + 120];
    if (!rc && have_lines && !ws_drawing_lines_match(lines_dir, &scene.split[split], scene.width, scene.height, why,
                                                     sizeof why)) {
        fprintf(stderr, "wiresketch: warning: %s; the drawing is not scored\n", why);
        have_lines = 0;
    }
    if (!rc && have_lines)
        rc = score_drawings(&scene, split, &curves, curves_path, lines_dir, &drawing, &drawing_curves, st);
    ws_surface_curve *per = NULL;
    if (!rc && per_curve) rc = surface_by_curve(gt_points, &g, curves.n, &per, st);
    /* The coverage needs the photos, which a measure of the cameras alone
     * does not: a scene whose photos cannot be read is still measured,
     * with a warning in place of the coverage. */
    const ws_scene *seen = lo ? &scene : &photos;
    if (!rc && coverage && !lo) {
        ws_status photo_st;
        ws_status_clear(&photo_st);
        sopt.load_images = 1;
        if (ws_roi_load_scene(&photos, scene_dir, &sopt, bbox ? box : NULL, NULL, NULL, &photo_st)) {
            fprintf(stderr, "wiresketch: warning: %s; the ground truth's coverage of the photos is not measured\n",
                    photo_st.msg);
            coverage = 0;
        }
    }
    if (!rc && coverage) rc = ws_view_targets_create(&targets, seen, st);
    if (!rc && coverage) rc = ws_scene_gt_coverage(seen, targets, gt_points, gt_curves, &cov, st);
    if (!rc) {
        const eval_result r = {split_name, scene.split[split].n, curves.n, g.n, lo ? loss_name : NULL, mean, &q, per,
                               have_lines ? &drawing : NULL, have_lines ? &drawing_curves : NULL,
                               coverage ? &cov : NULL};
        print_result(&r);
        if (coverage && cov.flagged) fprintf(stderr, "wiresketch: warning: %s\n", cov.line);
    }
    free(per);
    ws_view_targets_free(targets);
    ws_objective_free(obj);
    ws_view_targets_free(line_targets);
    ws_edge_consensus_free(&consensus);
    ws_gaussians_free(&g);
    ws_curves_free(&curves);
    ws_scene_free(&photos);
    ws_scene_free(&scene);
    return rc;
}

int cmd_eval(int argc, char **argv) {
    const char *curves_path = NULL, *split_name = "test", *loss_name = "auto", *background = "black";
    const char *edge_maps = NULL, *geometric = "blocks", *hidden = NULL, *masks = NULL;
    const char *gt_points = NULL, *gt_curves = NULL, *bbox = NULL;
    double edges_weight = 1.0;
    int size = 224, threads = 0, per_curve = 0;
    ws_arg_list layers = {0};
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    ws_splat_options so;
    ws_splat_options_default(&so);
    const ws_arg args[] = {
        WS_ROW_CURVES(&curves_path),
        {"--gt", WS_ARG_STRING, &gt_points, 0, "ground-truth point cloud (PLY) [SCENE/gt_points.ply if present]"},
        WS_ROW_GT_CURVES(&gt_curves),
        WS_ROW_SPLIT(&split_name),
        WS_ROW_BACKGROUND(&background),
        WS_ROW_MASKS(&masks),
        WS_ROW_EDGE_MAPS(&edge_maps),
        WS_ROW_BBOX(&bbox),
        WS_ROW_LOSS_OR_NONE(&loss_name),
        WS_ROW_WEIGHTS(&lo.weights_path),
        WS_ROW_LAYER_WEIGHTS(&layers),
        WS_ROW_GEOMETRIC(&geometric),
        WS_ROW_HIDDEN(&hidden),
        WS_ROW_EDGES_WEIGHT(&edges_weight),
        WS_ROW_SIZE(&size),
        WS_ROW_CUTOFF(&so.cutoff),
        WS_ROW_THREADS(&threads),
        {"--per-curve", WS_ARG_FLAG, &per_curve, 0,
         "also surface_curves: per curve, its Gaussians, their mean distance, what they add to surface_mean and how many lie beyond surface_p90"},
    };
    ws_command_spec spec = {"eval SCENE --curves C.json [--gt POINTS.ply] [--gt-curves C.json] [options]",
                            "test loss and distance to the ground truth of a sketch, as JSON", args,
                            (int)(sizeof args / sizeof args[0]), 1, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) return done;
    if (!curves_path) {
        ws_fail(&st, WS_EUSAGE, "--curves: required");
        return ws_cli_fail(&st);
    }
    const char *given_loss = loss_name;
    loss_name = ws_cli_auto_loss(loss_name, lo.weights_path);
    int with_loss = strcmp(loss_name, "none") != 0;
    ws_scene_options sopt;
    ws_scene_options_default(&sopt);
    sopt.width = sopt.height = size;
    sopt.edge_maps_dir = edge_maps;
    sopt.masks_dir = masks;
    ws_progress progress;
    ws_progress_init(&progress);
    sopt.progress = &progress;
    if (ws_cli_background(background, sopt.background, &sopt.background_auto, &st) ||
        ws_cli_check_size(size, &st) ||
        (with_loss && ws_cli_choose_loss(loss_name, edges_weight, &layers, geometric, hidden, &lo, &st)))
        return ws_cli_fail(&st);
    char scene_points[WS_PATH_MAX], scene_curves[WS_PATH_MAX];
    ws_scene_ground_truth(pos[0], scene_points, scene_curves);
    if (!gt_points) gt_points = scene_points[0] ? scene_points : NULL;
    if (!gt_curves) gt_curves = scene_curves[0] ? scene_curves : NULL;
    char lines_dir[WS_PATH_MAX];
    if (!with_loss && !gt_points && !gt_curves && !ws_drawing_lines_dir(pos[0], split_name, lines_dir)) {
        ws_fail(&st, WS_EUSAGE,
                "nothing to evaluate: --loss none and no ground truth (give --gt or --gt-curves; %s/lines/%s "
                "has no reference lines)", pos[0], split_name);
        return ws_cli_fail(&st);
    }
    if (per_curve && !(gt_points && *gt_points)) {
        ws_fail(&st, WS_EUSAGE, "--per-curve: no ground-truth point cloud to measure against (give --gt)");
        return ws_cli_fail(&st);
    }
    if (ws_runtime_init(threads, &st)) return ws_cli_fail(&st);
    ws_cli_announce_loss(given_loss, lo.weights_path);
    if (evaluate_sketch(pos[0], curves_path, split_name, &sopt, loss_name, bbox, with_loss ? &lo : NULL,
                        &so, gt_points, gt_curves, per_curve, &st))
        return ws_cli_fail(&st);
    return 0;
}
