/* init.c: initial curves and the scene check of a new fit (see init.h). */
#include <stdio.h>
#include <string.h>
#include "fit/init.h"
#include "geometry/check.h"

int ws_fit_init_curves(const ws_fit_options *o, const ws_scene *scene, const ws_scene_hull *hull, ws_rng *rng,
                       ws_curves *c, ws_status *st) {
    if (!strcmp(o->init_curves, "random"))
        return ws_curves_init_random(c, o->n_curves, scene->center, o->radius, o->length,
                                     o->thickness, o->overlap, rng, st);
    if (!strcmp(o->init_curves, "hull") || !strcmp(o->init_curves, "edges")) /* edges: fit.c moves them */
        return ws_curves_init_hull(c, &hull->surface, o->n_curves, o->length, o->thickness, o->overlap, rng, st);
    if (ws_curves_load(o->init_curves, c, st)) return st->code;
    if (c->n == 0)
        return ws_fail(st, WS_EINPUT, "%s: no curves (a fit starts from at least one)", o->init_curves);
    return WS_OK;
}

int ws_fit_check_scene(const ws_scene *scene, ws_view_targets *targets, char warning[WS_CHECK_LINE],
                       ws_status *st) {
    const ws_silhouette *sil[WS_NSPLITS];
    for (int s = 0; s < WS_NSPLITS; s++)
        if (ws_view_targets_silhouettes(targets, s, &sil[s], st)) return st->code;
    ws_check_report r;
    if (ws_check_scene(scene, sil, WS_CHECK_RESOLUTION, &r, st)) return st->code;
    warning[0] = 0;
    int rc = WS_OK;
    if (ws_check_warning_only(&r))
        snprintf(warning, WS_CHECK_LINE, "%.900s (%s)", r.line,
                 r.no_silhouette ? "a fit goes on with the edges the views agree on in the region of interest"
                                 : "a focal estimate alone does not stop a fit");
    else if (!r.consistent)
        rc = ws_fail(st, WS_EINPUT, "%.900s (or go on anyway with --no-check)", r.line);
    ws_check_report_free(&r);
    return rc;
}

int ws_fit_consensus(const ws_roi *roi, const ws_status *roi_st, const ws_scene *scene, ws_view_targets *targets,
                     ws_edge_consensus *c, char line[WS_CHECK_LINE], ws_status *st) {
    memset(c, 0, sizeof *c);
    line[0] = 0;
    if (roi_st->code || roi->source != WS_ROI_USER) {
        const ws_silhouette *sil;
        int empty, edge;
        if (ws_view_targets_silhouettes(targets, WS_TRAIN, &sil, st)) return st->code;
        if (ws_check_silhouettes_usable(sil, scene->split[WS_TRAIN].n, &empty, &edge)) return WS_OK;
    }
    if (roi_st->code) {
        *st = *roi_st;
        return st->code;
    }
    if (ws_edge_consensus_make(scene, roi, WS_CONSENSUS_RESOLUTION, c, st)) return st->code;
    if (c->hull.occupied)
        snprintf(line, WS_CHECK_LINE, "%.400s; the photos' colours agree on %ld of its %ld grid cubes (spacing "
                 "%.3g), and %d lie on edges the train views that see them agree on, the lines the fit draws",
                 roi->line, c->hull.kept, c->tested, c->voxel, c->n);
    else
        snprintf(line, WS_CHECK_LINE, "%.400s; the photos' colours do not tell the object from the room (too few "
                 "views, or one colour all round), and %d of its %ld grid points (spacing %.3g) lie on edges the "
                 "train views agree on, the lines the fit draws", roi->line, c->n, c->tested, c->voxel);
    if (c->solid) {
        const size_t used = strlen(line);
        snprintf(line + used, WS_CHECK_LINE - used, "; the colours' hull is a solid's (%.0f cubes a kept point), so "
                 "its outline in each view is taken convex", (double)c->hull.kept / c->n);
    }
    if (c->support.found) {
        const size_t used = strlen(line);
        snprintf(line + used, WS_CHECK_LINE - used, "; the object stands on a flat support across (%.2f, %.2f, %.2f) "
                 "that fills %.0f%% of the region: the %ld cubes of air the colours left on it were carved, and its own "
                 "lines left out", c->support.normal[0], c->support.normal[1], c->support.normal[2],
                 100 * c->support.share, c->support.carved);
    }
    ws_view_targets_set_consensus(targets, c);
    return WS_OK;
}
