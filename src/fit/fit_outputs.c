/* fit_outputs.c: the output directory of a fit (see fit_outputs.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/paths.h"
#include "metrics/drawing_score.h"
#include "objective/line_evidence.h"
#include "metrics/quality.h"
#include "io/export.h"
#include "fit/fit_outputs.h"
#include "io/gif.h"
#include "io/image.h"
#include "base/outfile.h"
#include "io/report.h"
#include "io/turntable.h"

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

/* test/NAME.png (the sketch) and test/NAME_photo.png for every test view;
 * fills the report's view list (paths relative to the output directory). */
static int write_tests(const char *out, const ws_scene *scene, const ws_curves *c,
                       ws_sketch_renderer *r, ws_drawing_hull *dh, const double *losses, ws_report_view *views,
                       char (*paths)[2][300], ws_status *st) {
    const ws_split *test = &scene->split[WS_TEST];
    if (test->n == 0) return WS_OK;
    char dir[PATH_BYTES], path[PATH_BYTES];
    join(dir, out, "test");
    if (ws_mkdir(dir, st)) return st->code;
    for (int v = 0; v < test->n; v++) {
        const ws_view *view = &test->views[v];
        snprintf(paths[v][0], 300, "test/%s.png", view->name);
        snprintf(paths[v][1], 300, "test/%s_photo.png", view->name);
        if (ws_sketch_render(r, c, &view->cam, st) ||
            (dh && ws_drawing_hull_render(dh, &view->cam, r->gray, r->gray, st)) ||
            write_gray_png(join(path, out, paths[v][0]), r, st) ||
            ws_png_write(join(path, out, paths[v][1]), &view->photo, st))
            return st->code;
        views[v] = (ws_report_view){view->name, paths[v][0], paths[v][1], losses ? losses[v] : NAN};
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
static int write_metrics(const char *path, const ws_fit_state *s, int retired, double test_loss,
                         const ws_quality *q, const ws_drawing_score *drawing, ws_status *st) {
    /* drawing: NULL, or the drawing's score and the curves' alone */
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "{\"steps\": %ld, \"skipped_steps\": %ld, \"respawned_curves\": %ld, \"retired_curves\": %d, "
            "\"seconds\": %.3f", s->global_step, s->skipped_steps, s->respawned, retired, s->elapsed);
    if (isfinite(test_loss)) fprintf(f.fp, ", \"test_loss\": %.9g", test_loss);
    if (q->have_surface)
        fprintf(f.fp, ", \"surface_mean\": %.9g, \"surface_p90\": %.9g, \"surface_precision\": %.9g, "
                "\"surface_stray_curves\": %d", q->surface.mean, q->surface.p90,
                q->surface_strays.precision, q->surface_strays.stray_curves);
    if (q->have_curves)
        fprintf(f.fp, ", \"chamfer\": %.9g, \"fscore\": %.9g, \"recall\": %.9g, \"gaussian_precision\": %.9g, "
                "\"stray_curves\": %d", q->curves.chamfer, q->curves.fscore, q->curves.recall,
                q->curve_strays.precision, q->curve_strays.stray_curves);
    if (q->have_curves) {
        fprintf(f.fp, ", ");
        ws_line_metrics_json(f.fp, &q->lines);
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
                        const ws_fit_state *s, const ws_curves *sketch, int retired,
                        const ws_report_view *views, double test_loss, const ws_quality *q,
                        const ws_drawing_score *drawing, ws_status *st) {
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
    char text[22][64];
    snprintf(text[1], 64, "%ld (%ld skipped; %ld respawned, %d retired)", s->global_step,
             s->skipped_steps, s->respawned, retired);
    snprintf(text[2], 64, "%.6g", test_loss);
    ws_report_item metrics[16] = {{"steps", text[1]}, {"test loss (item 0)", text[2]}};
    int nmetrics = 2;
    if (q->have_surface) {
        snprintf(text[8], 64, "%.5f", q->surface.mean);
        snprintf(text[9], 64, "%.5f", q->surface.p90);
        metrics[nmetrics++] = (ws_report_item){"surface distance, mean / diagonal", text[8]};
        metrics[nmetrics++] = (ws_report_item){"surface distance, 90th percentile / diagonal", text[9]};
        snprintf(text[12], 64, "%.4f (%d stray of %d)", q->surface_strays.precision,
                 q->surface_strays.stray_curves, q->surface_strays.n_curves);
        metrics[nmetrics++] = (ws_report_item){"Gaussians within 1% of the diagonal of the surface", text[12]};
    }
    if (q->have_curves) {
        snprintf(text[10], 64, "%.5f", q->curves.chamfer);
        snprintf(text[11], 64, "%.4f", q->curves.fscore);
        metrics[nmetrics++] = (ws_report_item){"curve Chamfer / diagonal", text[10]};
        metrics[nmetrics++] = (ws_report_item){"curve F-score at 1% of the diagonal", text[11]};
        snprintf(text[13], 64, "%.4f / %.4f", q->curve_strays.precision, q->curves.recall);
        metrics[nmetrics++] = (ws_report_item){"precision over Gaussians / recall over arc length, at 1%", text[13]};
        snprintf(text[14], 64, "%d of %d", q->curve_strays.stray_curves, q->curve_strays.n_curves);
        metrics[nmetrics++] = (ws_report_item){"stray curves (most Gaussians beyond 5% of the diagonal)", text[14]};
        const ws_line_metrics *l = &q->lines;
        snprintf(text[16], 64, "%.4f / %.4f / %.4f", l->accuracy, l->completeness, l->chamfer);
        snprintf(text[17], 64, "%.3f / %.3f / %.3f", l->precision[0], l->recall[0], l->fscore[0]);
        snprintf(text[18], 64, "%.3f / %.3f / %.3f", l->precision[1], l->recall[1], l->fscore[1]);
        metrics[nmetrics++] = (ws_report_item){"accuracy / completeness / Chamfer (their sum), over the largest side", text[16]};
        metrics[nmetrics++] = (ws_report_item){"precision / recall / F-score at 1% of the largest side", text[17]};
        metrics[nmetrics++] = (ws_report_item){"precision / recall / F-score at 2% of the largest side", text[18]};
    }
    if (drawing) {
        const ws_drawing_score *d = drawing;
        snprintf(text[19], 64, "%.3f / %.3f / %.3f", d->precision[0], d->recall[0], d->fscore[0]);
        snprintf(text[20], 64, "%.3f / %.3f / %.2f", d->contour_recall[0], d->scribble[0], d->overdraw);
        snprintf(text[21], 64, "%.3f / %.3f / %.3f", d->precision[1], d->recall[1], d->fscore[1]);
        metrics[nmetrics++] = (ws_report_item){"drawing: precision / recall / F at 1% of the image diagonal", text[19]};
        metrics[nmetrics++] =
            (ws_report_item){"drawing: contour recall / interior scribble at 1%; overdraw", text[20]};
        metrics[nmetrics++] = (ws_report_item){"drawing: precision / recall / F at 0.5% of the image diagonal", text[21]};
    }
    ws_report_image images[] = {{"turntable", "turntable.gif"}, {"evolution during the fit", "evolution.gif"}};
    ws_report rep = {0};
    rep.title = "wiresketch fit";
    rep.scene_path = scene->dir;
    rep.settings = opt->settings;
    rep.n_settings = opt->settings ? opt->n_settings : 0;
    rep.metrics = metrics;
    rep.n_metrics = nmetrics;
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

int ws_fit_write_outputs(const ws_fit_options *opt, const ws_scene *scene, const ws_fit_state *s,
                         const int *retire, const double *test_losses, double test_loss, ws_status *st) {
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
    if (!rc) rc = write_metrics(join(path, out, "metrics.json"), s, retired, test_loss, &q, scored, st);
    if (!rc) rc = ws_curves_save(join(path, out, "curves.json"), &c, st);
    if (!rc) rc = ws_export_obj(join(path, out, "curves.obj"), &c, st);
    if (!rc) rc = ws_export_ply(join(path, out, "curves.ply"), &c, st);
    if (!rc) rc = write_log(join(path, out, "log.csv"), s, st);
    if (!rc) rc = write_tests(out, scene, &c, &r, have_hull ? &dh : NULL, test_losses, views, paths, st);
    if (!rc) rc = write_evolution(join(path, out, "evolution.gif"), scene, s, &r, st);
    if (!rc)
        rc = ws_turntable_gif(join(path, out, "turntable.gif"), &c, scene->center, distance,
                              scene->camera_angle_x, scene->width, TURNTABLE_FRAMES, st);
    if (!rc)
        rc = write_report(join(path, out, "report.html"), opt, scene, s, &c, retired, ntest ? views : NULL,
                          test_loss, &q, scored, st);
    if (have_hull) ws_drawing_hull_free(&dh);
    free(views);
    free(paths);
    ws_sketch_renderer_free(&r);
    ws_curves_free(&c);
    return rc;
}
