/* fit_explained.h: how much of what the photos show a fit's curves explain
 * (docs/METHOD.md section 17): the share of the training views' line
 * target pixels (view_targets.h: value >= 1/2) that lie within
 * WS_EXPLAINED_TAU of the image diagonal of a stroke (the sketch render's
 * ink, alpha >= 1/2), over all training views together. It is high where
 * the strokes lie on the lines the photos show and low where they are
 * nowhere near them: an object over a busy background without a mask,
 * whose lines are the background's. A fit below WS_EXPLAINED_MIN ends
 * with a warning that gives the figure. */
#ifndef WS_FIT_EXPLAINED_H
#define WS_FIT_EXPLAINED_H
#include "io/scene.h"
#include "io/turntable.h"
#include "objective/view_targets.h"
#include "render/curves.h"
#include "nn/base/status.h"

#define WS_EXPLAINED_TAU 0.01
#define WS_EXPLAINED_MIN 0.2

/* *share: the figure for curves c (NaN when the training views have no
 * line pixel); r: a renderer of the scene's working size. */
int ws_fit_explained(const ws_scene *scene, ws_view_targets *targets, const ws_curves *c, ws_sketch_renderer *r,
                     double *share, ws_status *st);

/* The warning's line when share is below WS_EXPLAINED_MIN, else "". */
void ws_fit_explained_line(double share, int width, int height, char *line, size_t size);

#endif
