/* fit_outputs.c: the output directory of a fit (see fit_outputs.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/json_number.h"
#include "base/paths.h"
#include "metrics/drawing_score.h"
#include "objective/line_evidence.h"
#include "metrics/quality.h"
#include "io/export.h"
#include "fit/fit_explained.h"
#include "fit/fit_metrics.h"
#include "fit/fit_outputs.h"
#include "fit/fit_time.h"
#include "objective/lines.h"
#include "objective/scene_gt_coverage.h"
#include "io/gif.h"
#include "io/image.h"
#include "base/outfile.h"
#include "io/report.h"
#include "io/turntable.h"

/* The files of the output directory, by what they hold. */
enum { OUT_METRICS, OUT_CURVES, OUT_OBJ, OUT_PLY, OUT_LOG, OUT_EVOLUTION, OUT_TURNTABLE, OUT_REPORT, OUT_FILES };
static const char *const output_files[OUT_FILES] = {"metrics.json", "curves.json", "curves.obj",   "curves.ply",
                                                    "log.csv",      "evolution.gif", "turntable.gif", "report.html"};

#define TURNTABLE_FRAMES 72
#define EVOLUTION_DELAY_CS 10

/* dir/name in dst (PATH_BYTES); returns dst so that calls nest. */
#define PATH_BYTES 4600
static const char *join(char *dst, const char *dir, const char *name) {
    snprintf(dst, PATH_BYTES, "%s/%s", dir, name);
    return dst;
}

static int write_log(const char *path, const ws_fit_state *s, ws_status *st) {
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "batch,step,seconds,train_loss,val_loss\n");
    for (int i = 0; i < s->nlog; i++) {
        const ws_log_row *r = &s->log[i];
        fprintf(f.fp, "%d,%ld,%.3f,%.9g,", r->batch, r->step, r->seconds, r->train_loss);
        if (isfinite(r->val_loss)) fprintf(f.fp, "%.9g", r->val_loss);
        fputc('\n', f.fp);
    }
    return ws_outfile_commit(&f, st);
}

/* Writes a renderer's gray sketch as an 8-bit PNG. */
static int write_gray_png(const char *path, const ws_sketch_renderer *r, ws_status *st) {
    ws_image img;
    if (ws_image_alloc(&img, r->width, r->height, 1, st)) return st->code;
    for (int i = 0; i < r->width * r->height; i++) img.data[i] = r->gray[i] / 255.0f;
    int rc = ws_png_write(path, &img, st);
    ws_image_free(&img);
    return rc;
}

/* The square the report shows a test view in: around the object, which is
 * the photo's (its mask, else what differs from its background by more
 * than 0.1) and the sketch's ink together, with a margin of a tenth of
 * its side and at least 16 px; crop[2] = 0 when neither shows anything. */
static void object_square(const ws_view *view, const unsigned char *gray, const float background[3], int W, int H,
                          int crop[3]) {
    int x0 = W, y0 = H, x1 = -1, y1 = -1;
    const size_t plane = (size_t)W * H;
    const float *photo = view->photo.data, *mask = view->mask.data;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            size_t k = (size_t)i * W + j;
            int object = gray[k] < 250;
            if (mask)
                object |= mask[k] >= 0.5f;
            else
                for (int c = 0; c < 3 && !object; c++) object = fabsf(photo[c * plane + k] - background[c]) > 0.1f;
            if (!object) continue;
            if (j < x0) x0 = j;
            if (j > x1) x1 = j;
            if (i < y0) y0 = i;
            if (i > y1) y1 = i;
        }
    crop[0] = crop[1] = crop[2] = 0;
    if (x1 < 0) return;
    int side = (x1 - x0 > y1 - y0 ? x1 - x0 : y1 - y0) + 1;
    side += side / 5 > 16 ? side / 5 : 16;
    if (side > W) side = W;
    if (side > H) side = H;
    int x = (x0 + x1 + 1 - side) / 2, y = (y0 + y1 + 1 - side) / 2;
    crop[0] = x < 0 ? 0 : x + side > W ? W - side : x;
    crop[1] = y < 0 ? 0 : y + side > H ? H - side : y;
    crop[2] = side;
}

/* test/NAME.png (the sketch) and test/NAME_photo.png for every test view;
 * fills the report's view list (paths relative to the output directory). */
static int write_tests(const char *out, const ws_scene *scene, const ws_curves *c, const float background[3],
                       ws_sketch_renderer *r, ws_drawing_hull *dh, const double *losses, ws_report_view *views,
                       char (*paths)[2][300], ws_status *st) {
    const ws_split *test = &scene->split[WS_TEST];
    if (test->n == 0) return WS_OK;
    char dir[PATH_BYTES], path[PATH_BYTES];
    join(dir, out, "test");
    if (ws_mkdir_inside(dir, st)) return st->code;
    for (int v = 0; v < test->n; v++) {
        const ws_view *view = &test->views[v];
        snprintf(paths[v][0], 300, "test/%s.png", view->name);
        snprintf(paths[v][1], 300, "test/%s_photo.png", view->name);
        if (ws_sketch_render(r, c, &view->cam, st) ||
            (dh && ws_drawing_hull_render(dh, &view->cam, r->gray, r->gray, st)) ||
            write_gray_png(join(path, out, paths[v][0]), r, st) ||
            ws_png_write(join(path, out, paths[v][1]), &view->photo, st))
            return st->code;
        views[v] = (ws_report_view){view->name, paths[v][0], paths[v][1], losses ? losses[v] : NAN, r->width, {0}};
        object_square(view, r->gray, background, r->width, r->height, views[v].crop);
    }
    return WS_OK;
}

/* evolution.gif: the sketch at every snapshot, seen from the first test
 * view (or the first training view). */
static int write_evolution(const char *path, const ws_scene *scene, const ws_fit_state *s,
                           ws_sketch_renderer *r, ws_status *st) {
    const ws_split *sp = scene->split[WS_TEST].n ? &scene->split[WS_TEST] : &scene->split[WS_TRAIN];
    ws_curves frame = s->curves;
    ws_gif gif;
    if (ws_gif_open(&gif, path, r->width, r->height, 1, EVOLUTION_DELAY_CS, st)) return st->code;
    for (int k = 0; k < s->nsnap; k++) {
        frame.P = s->snapshots + (size_t)k * s->curves.n * WS_CURVE_FLOATS;
        if (ws_sketch_render(r, &frame, &sp->views[0].cam, st) || ws_gif_add_frame(&gif, r->gray, st)) {
            ws_gif_abort(&gif);
            return st->code;
        }
    }
    return ws_gif_commit(&gif, st);
}

/* metrics.json: the numbers of the report, for scripts. */
static int write_metrics(const char *path, const ws_fit_state *s, int retired, double test_loss, double explained,
                         const ws_quality *q, const ws_fit_metrics *m, const ws_gt_coverage *cov,
                         const ws_drawing_score *drawing, ws_status *st) {
    /* drawing: NULL, or the drawing's score and the curves' alone */
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "{\"steps\": %ld, \"skipped_steps\": %ld, \"curves\": %d, \"respawned_curves\": %ld, "
            "\"retired_curves\": %d, \"seconds\": %.3f", s->global_step, s->skipped_steps, s->curves.n, s->respawned,
            retired, s->elapsed);
    if (isfinite(test_loss)) fprintf(f.fp, ", \"test_loss\": %.9g", test_loss);
    if (isfinite(explained)) fprintf(f.fp, ", \"explained\": %.4f", explained);
    const char *const surface_keys[3] = {"surface_mean", "surface_p90", "surface_precision"};
    const double surface[3] = {q->surface.mean, q->surface.p90, q->surface_strays.precision};
    for (int k = 0; k < 3 && q->have_surface; k++) {
        fputs(", ", f.fp);
        ws_json_number(f.fp, surface_keys[k], surface[k], 9);
    }
    if (q->have_surface) fprintf(f.fp, ", \"surface_stray_curves\": %d", q->surface_strays.stray_curves);
    const char *const curve_keys[4] = {"chamfer", "fscore", "recall", "gaussian_precision"};
    const double curve[4] = {q->curves.chamfer, q->curves.fscore, q->curves.recall, q->curve_strays.precision};
    for (int k = 0; k < 4 && q->have_curves; k++) {
        fputs(", ", f.fp);
        ws_json_number(f.fp, curve_keys[k], curve[k], 9);
    }
    if (q->have_curves) {
        fprintf(f.fp, ", \"stray_curves\": %d, ", q->curve_strays.stray_curves);
        ws_line_metrics_json(f.fp, &q->lines);
    }
    fprintf(f.fp, ", ");
    ws_fit_metrics_verdicts_json(f.fp, m);
    if (cov) {
        fprintf(f.fp, ", ");
        ws_gt_coverage_json(f.fp, cov);
    }
    if (drawing) {
        fprintf(f.fp, ", ");
        ws_drawing_score_json(f.fp, "drawing", &drawing[0]);
        fprintf(f.fp, ", ");
        ws_drawing_score_json(f.fp, "drawing_curves", &drawing[1]);
    }
    fprintf(f.fp, "}\n");
    return ws_outfile_commit(&f, st);
}

static int write_report(const char *path, const ws_fit_options *opt, const ws_scene *scene,
                        const ws_fit_state *s, const ws_curves *sketch, const ws_report_view *views,
                        const ws_fit_metrics *m, const char *warning, int drawn, ws_status *st) {
    int nval = 0;
    long *steps = ws_malloc((size_t)(s->nlog + 1) * 2 * sizeof(long), "report", st);
    double *losses = steps ? ws_malloc((size_t)(s->nlog + 1) * 2 * sizeof(double), "report", st) : NULL;
    if (!losses) {
        free(steps);
        return st->code;
    }
    long *val_steps = steps + s->nlog + 1;
    double *val_losses = losses + s->nlog + 1;
    for (int i = 0; i < s->nlog; i++) {
        steps[i] = s->log[i].step;
        losses[i] = s->log[i].train_loss;
        if (isfinite(s->log[i].val_loss)) {
            val_steps[nval] = s->log[i].step;
            val_losses[nval++] = s->log[i].val_loss;
        }
    }
    /* the line loss's coarse-to-fine phases (fit_time.h), where it has them */
    int ntrain = scene->split[WS_TRAIN].n, bs = opt->batch_size > 0 ? opt->batch_size : 1;
    long schedule = (long)opt->epochs * ((ntrain + bs - 1) / bs) * opt->inner_steps, first[WS_FIT_TIME_PHASES + 1];
    int levels[WS_FIT_TIME_PHASES], lines = opt->loss.lines_weight != 0;
    int nphases = lines ? ws_fit_time_boundaries(s->global_step, schedule, 1, first, levels) : 0;
    char labels[WS_FIT_TIME_PHASES][48];
    const char *label_ptr[WS_FIT_TIME_PHASES];
    for (int k = 0; k < nphases; k++) {
        snprintf(labels[k], sizeof labels[k], "%d of %d levels", levels[k], WS_LINES_LEVELS);
        label_ptr[k] = labels[k];
    }
    /* the training cameras: centre and viewing direction (-z) */
    const ws_split *train = &scene->split[WS_TRAIN];
    double *cameras = ws_malloc((size_t)(train->n ? train->n : 1) * 6 * sizeof(double), "report", st);
    if (!cameras) {
        free(steps);
        free(losses);
        return st->code;
    }
    for (int v = 0; v < train->n; v++)
        for (int i = 0; i < 3; i++) {
            cameras[6 * v + i] = train->views[v].cam.c2w[i][3];
            cameras[6 * v + 3 + i] = -train->views[v].cam.c2w[i][2];
        }
    /* drawn: the test views and the turntable show the drawing (the curves
     * and the visual hull's lines), the evolution and the 3D view the curves */
    ws_report_image images[] = {
        {drawn ? "turntable: the drawing (the curves and the visual hull's outline)" : "turntable",
         output_files[OUT_TURNTABLE]},
        {"evolution of the curves during the fit", output_files[OUT_EVOLUTION]}};
    ws_report rep = {0};
    rep.title = "wiresketch fit";
    rep.scene_path = scene->dir;
    rep.settings = opt->settings;
    rep.n_settings = opt->settings ? opt->n_settings : 0;
    rep.metrics = m->items;
    rep.n_metrics = m->n;
    rep.warning = warning;
    rep.phase_step = first;
    rep.phase_label = label_ptr;
    rep.n_phases = nphases > 1 ? nphases : 0;
    rep.phase_note = "Dashed lines: the line loss brings in its finer levels as the fit goes (coarse to fine, "
                     "docs/METHOD.md, the line loss). Each level it adds is a harder comparison, so the training "
                     "loss climbs where a phase begins: the fit is not getting worse. Validation always uses "
                     "every level.";
    rep.cameras = cameras;
    rep.n_cameras = train->n;
    rep.train_step = steps;
    rep.train_loss = losses;
    rep.n_train = s->nlog;
    rep.val_step = val_steps;
    rep.val_loss = val_losses;
    rep.n_val = nval;
    rep.tests = views;
    rep.n_tests = views ? scene->split[WS_TEST].n : 0;
    rep.images = images;
    rep.n_images = 2;
    rep.wall_seconds = s->elapsed;
    rep.curves = sketch;
    int rc = ws_report_write(path, &rep, st);
    free(cameras);
    free(steps);
    free(losses);
    return rc;
}

/* The sketch the outputs show: c less the curves marked in retire, unless
 * that would leave none; *retired: how many were left out. */
static int final_sketch(const ws_curves *c, const int *retire, ws_curves *sketch, int *retired,
                        ws_status *st) {
    *retired = 0;
    for (int ci = 0; ci < c->n; ci++) *retired += retire[ci] != 0;
    if (*retired == c->n) *retired = 0;
    if (ws_curves_alloc(sketch, c->n - *retired, st)) return st->code;
    sketch->thickness = c->thickness;
    sketch->overlap = c->overlap;
    for (int ci = 0, k = 0; ci < c->n; ci++)
        if (!*retired || !retire[ci])
            memcpy(sketch->P + (size_t)k++ * WS_CURVE_FLOATS, c->P + (size_t)ci * WS_CURVE_FLOATS,
                   sizeof(double) * WS_CURVE_FLOATS);
    return WS_OK;
}

int ws_fit_outputs_check(const char *out_dir, ws_status *st) {
    char path[PATH_BYTES];
    for (int k = 0; k < OUT_FILES; k++)
        if (ws_outfile_check(join(path, out_dir, output_files[k]), st)) return st->code;
    return WS_OK;
}

int ws_fit_write_outputs(const ws_fit_options *opt, const ws_scene *scene, ws_view_targets *fit_targets,
                         const ws_fit_state *s, const int *retire, const double *test_losses, double test_loss,
                         ws_status *st) {
    const char *out = opt->out_dir;
    char path[PATH_BYTES];
    ws_sketch_renderer r;
    ws_curves c = {0};
    int retired;
    if (final_sketch(&s->curves, retire, &c, &retired, st)) return st->code;
    if (ws_sketch_renderer_init(&r, scene->width, scene->height, st)) {
        ws_curves_free(&c);
        return st->code;
    }
    int ntest = scene->split[WS_TEST].n;
    ws_report_view *views = ws_calloc(ntest ? ntest : 1, sizeof *views, "report", st);
    char(*paths)[2][300] = views ? ws_malloc((size_t)(ntest ? ntest : 1) * sizeof *paths, "report", st) : NULL;
    int rc = paths ? WS_OK : st->code;
    double distance = ws_turntable_distance(&scene->split[WS_TRAIN], scene->center);
    char gt_points[WS_PATH_MAX], gt_curves[WS_PATH_MAX];
    ws_scene_ground_truth(scene->dir, gt_points, gt_curves);
    ws_quality q;
    ws_drawing_score drawing[2]; /* the drawing's score, the curves' alone */
    char lines_dir[WS_PATH_MAX];
    int have_lines = ntest && ws_drawing_lines_dir(scene->dir, "test", lines_dir);
    char why[WS_PATH_MAX + 120];
    if (have_lines && !ws_drawing_lines_match(lines_dir, &scene->split[WS_TEST], scene->width, scene->height, why,
                                              sizeof why)) {
        fprintf(stderr, "wiresketch: warning: %s; the drawing is not scored\n", why);
        have_lines = 0;
    }
    ws_drawing_hull dh;
    int have_hull = 0;
    if (!rc && ntest) {
        /* a scene whose silhouettes carve no hull is drawn by its curves alone */
        rc = ws_drawing_hull_make(&dh, scene, st);
        have_hull = rc == WS_OK;
        if (rc == WS_EINPUT) {
            fprintf(stderr, "wiresketch: warning: %s; the drawing is the curves alone\n", st->msg);
            rc = WS_OK;
        }
    }
    if (!rc) rc = ws_quality_measure(&c, gt_points, gt_curves, &q, st);
    if (!rc && have_lines)
        rc = ws_drawing_score_split(&scene->split[WS_TEST], scene->width, scene->height, &c, lines_dir,
                                    have_hull ? ws_drawing_hull_render : NULL, &dh, &drawing[0], st);
    if (!rc && have_lines)
        rc = ws_drawing_score_split(&scene->split[WS_TEST], scene->width, scene->height, &c, lines_dir, NULL, NULL,
                                    &drawing[1], st);
    const ws_drawing_score *scored = have_lines ? drawing : NULL;
    /* whether the ground truth holds all that the photos show: where it
     * misses a part, a fit that left that part out scores better */
    ws_gt_coverage cov;
    ws_view_targets *targets = NULL;
    int coverage = !rc && gt_points[0];
    if (coverage) rc = ws_view_targets_create(&targets, scene, st);
    if (coverage && !rc) rc = ws_scene_gt_coverage(scene, targets, gt_points, gt_curves, &cov, st);
    ws_view_targets_free(targets);
    double explained = NAN;
    char explained_line[600], warning[WS_GT_LINE + 160 + sizeof explained_line];
    if (!rc && fit_targets) rc = ws_fit_explained(scene, fit_targets, &c, &r, &explained, st);
    ws_fit_explained_line(explained, scene->width, scene->height, explained_line, sizeof explained_line);
    int n = 0; /* the report puts "Warning: " before the first */
    warning[0] = '\0';
    if (coverage && !rc && cov.flagged)
        n = snprintf(warning, sizeof warning, "%s. The distances to the ground truth do not see that part: a sketch "
                     "that left it out scores as well as one that drew it.", cov.line);
    if (explained_line[0])
        snprintf(warning + n, sizeof warning - n, "%s%s.", n ? " Warning: " : "", explained_line);
    ws_fit_metrics m;
    int lines_loss = opt->loss.lines_weight != 0 && !ws_loss_uses_clip(&opt->loss) && opt->loss.l2_weight == 0 &&
                     opt->loss.edges_weight == 0;
    if (!rc) ws_fit_metrics_fill(&m, s, retired, test_loss, lines_loss, &q);
    if (!rc) ws_fit_metrics_add_explained(&m, explained);
    if (!rc && scored) ws_fit_metrics_add_drawing(&m, scored);
    if (!rc)
        rc = write_metrics(join(path, out, output_files[OUT_METRICS]), s, retired, test_loss, explained, &q, &m,
                           coverage ? &cov : NULL, scored, st);
    if (!rc) rc = ws_curves_save(join(path, out, output_files[OUT_CURVES]), &c, st);
    if (!rc) rc = ws_export_obj(join(path, out, output_files[OUT_OBJ]), &c, st);
    if (!rc) rc = ws_export_ply(join(path, out, output_files[OUT_PLY]), &c, st);
    if (!rc) rc = write_log(join(path, out, output_files[OUT_LOG]), s, st);
    if (!rc) rc = write_tests(out, scene, &c, opt->background, &r, have_hull ? &dh : NULL, test_losses, views, paths, st);
    if (!rc) rc = write_evolution(join(path, out, output_files[OUT_EVOLUTION]), scene, s, &r, st);
    if (!rc)
        rc = ws_turntable_gif(join(path, out, output_files[OUT_TURNTABLE]), &c, scene->center, distance,
                              scene->camera_angle_x, scene->width, TURNTABLE_FRAMES,
                              have_hull ? ws_drawing_hull_render : NULL, &dh, st);
    if (!rc)
        rc = write_report(join(path, out, output_files[OUT_REPORT]), opt, scene, s, &c, ntest ? views : NULL, &m,
                          warning[0] ? warning : NULL, have_hull, st);
    if (!rc && explained_line[0]) fprintf(stderr, "wiresketch: warning: %s\n", explained_line);
    if (have_hull) ws_drawing_hull_free(&dh);
    free(views);
    free(paths);
    ws_sketch_renderer_free(&r);
    ws_curves_free(&c);
    return rc;
}
