/* init.h: where a fit's curves start, and the scene check a new fit passes
 * first.
 *
 * --init hull (the default): the curves start on the surface of the visual
 * hull of the training views (geometry/surface.h, WS_HULL_INIT_RESOLUTION
 * voxels along its longest side), spread by farthest-point sampling, as
 * short strokes tangent to it (hull: the fit's, carved once). --init edges:
 * the same, then before the first step every curve (all idle: no gradient
 * yet) is moved as a respawn moves an idle curve (fit/respawn.h): each onto
 * the training views' edge pixel farthest from the curves already placed,
 * at the depth the other views agree on, along the edge; the hull start
 * stays where no edge is left uncovered. fit.c does that move; here it is
 * the hull start. --init random: the original's sphere (METHOD.md section
 * 2). Anything else names a curve file. */
#ifndef WS_FIT_INIT_H
#define WS_FIT_INIT_H
#include "fit/fit_options.h"
#include "geometry/check.h"
#include "geometry/roi.h"
#include "geometry/surface.h"
#include "io/scene.h"
#include "nn/base/rng.h"
#include "objective/edge_consensus.h"
#include "objective/view_targets.h"
#include "render/curves.h"

/* hull: the training views' (geometry/surface.h), carved once by the fit;
 * read with --init hull. */
int ws_fit_init_curves(const ws_fit_options *o, const ws_scene *scene, const ws_scene_hull *hull, ws_rng *rng,
                       ws_curves *c, ws_status *st);

/* Fails with WS_EINPUT and the check's one line (geometry/check.h), which
 * ends naming --no-check, when the scene is not consistent; when its only
 * fault is the focal estimate of consistent splits, or that it has no
 * usable silhouette (ws_check_warning_only), it succeeds with that line and
 * why it goes on in warning instead ("" otherwise). It reads
 * the silhouettes of every split from targets. */
int ws_fit_check_scene(const ws_scene *scene, ws_view_targets *targets, char warning[WS_CHECK_LINE],
                       ws_status *st);

/* Where the train views have no usable silhouette (geometry/check.h:
 * ws_check_silhouettes_usable), or the user gave the box (roi's source
 * WS_ROI_USER), takes the region of interest the scene was loaded with
 * (geometry/roi.h ws_roi_load_scene: roi, or the failure roi_st holds)
 * and finds the edges the views agree on in it
 * (objective/edge_consensus.h), and hands them to targets, whose
 * silhouettes and line targets are theirs from then on; line: one line
 * that says so ("" and c empty otherwise). c must outlive targets' use.
 * The fit's targets and eval's are made here, so that eval's test loss is
 * the fit's kind of number. */
int ws_fit_consensus(const ws_roi *roi, const ws_status *roi_st, const ws_scene *scene, ws_view_targets *targets,
                     ws_edge_consensus *c, char line[WS_CHECK_LINE], ws_status *st);

#endif
