/* fit_explained.c: the share of the photos' lines a fit explains (see fit_explained.h). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "fit/fit_explained.h"
#include "render/distance.h"

static double tau_px(int width, int height) { return WS_EXPLAINED_TAU * hypot(width, height); }

int ws_fit_explained(const ws_scene *scene, ws_view_targets *targets, const ws_curves *c, ws_sketch_renderer *r,
                     double *share, ws_status *st) {
    const int W = scene->width, H = scene->height;
    const size_t n = (size_t)W * H;
    const double tau = tau_px(W, H);
    uint8_t *ink = ws_malloc(n, "the explained share", st);
    float *distance = ink ? ws_malloc(sizeof *distance * n, "the explained share", st) : NULL;
    int rc = distance ? WS_OK : st->code;
    double lines = 0, near = 0;
    const ws_split *train = &scene->split[WS_TRAIN];
    for (int v = 0; v < train->n && !rc; v++) {
        const float *target;
        if ((rc = ws_view_targets_line(targets, WS_TRAIN, v, &target, st)) ||
            (rc = ws_sketch_render(r, c, &train->views[v].cam, st)))
            break;
        for (size_t p = 0; p < n; p++) ink[p] = r->alpha[p] >= 0.5;
        if ((rc = ws_distance_map(ink, W, H, distance, st))) break;
        for (size_t p = 0; p < n; p++) {
            if (target[p] < 0.5f) continue;
            lines++;
            near += distance[p] <= tau; /* INFINITY (no ink) is never near */
        }
    }
    *share = lines > 0 ? near / lines : NAN;
    free(ink);
    free(distance);
    return rc;
}

void ws_fit_explained_line(double share, int width, int height, char *line, size_t size) {
    line[0] = '\0';
    if (!(share < WS_EXPLAINED_MIN)) return;
    snprintf(line, size,
             "the curves explain %.0f%% of the training views' lines (their line pixels within %.1f px of a "
             "stroke; below %.0f%% the strokes are not where the photos' lines are, e.g. an object over a busy "
             "background without masks: give --masks DIR or mask_path)",
             100 * share, tau_px(width, height), 100 * WS_EXPLAINED_MIN);
}
