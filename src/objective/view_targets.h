/* view_targets.h: what each view's photo says about the object, made once
 * per process and shared by everyone who reads it:
 *   - its silhouette (geometry/silhouette.h), which the scene check, the
 *     visual hull, the silhouette term, the respawn of idle curves and the
 *     line target read;
 *   - its line target (line_target.h), which the line loss and the respawn
 *     read.
 * Each is made the first time anyone asks for it and kept until
 * ws_view_targets_free (the line targets in a view_cache.h, the
 * silhouettes in one array per split). A fit makes one and hands it to
 * all of them (ws_loss_options.targets); a loss made alone makes its own.
 *
 * Memory, per view asked for: 5 bytes a pixel for the silhouette (its mask
 * and distance map), 4 for the line target; 452 KB at 224 x 224, so
 * 43.4 MB for the rose's 96 training views and 72.7 MB with its 32
 * validation and 33 test views (a fit with the line loss asks for all;
 * one without keeps the training silhouettes alone, 24.1 MB, see
 * ws_view_targets_release_setup).
 *
 * Not thread-safe: ask from serial code (a parallel loop takes what it
 * reads before it starts). */
#ifndef WS_VIEW_TARGETS_H
#define WS_VIEW_TARGETS_H
#include "geometry/silhouette.h"
#include "io/scene.h"
#include "objective/edge_consensus.h"
#include "objective/line_evidence.h"
#include "nn/base/status.h"

typedef struct ws_view_targets ws_view_targets;

/* For the views of a loaded scene (which must outlive it), holding nothing yet. */
int ws_view_targets_create(ws_view_targets **out, const ws_scene *scene, ws_status *st);
void ws_view_targets_free(ws_view_targets *t);

/* *out: the silhouettes of every view of `split` (scene->split[split].n of
 * them, in view order), each made on the first call that needs it. */
int ws_view_targets_silhouettes(ws_view_targets *t, int split, const ws_silhouette **out, ws_status *st);

/* *out: the line target (H x W) of view `view` of `split`: the user's own
 * edge map where the view has one (scene.h: edge_path, --edge-maps), else
 * ws_line_target of its photo, mask and silhouette; made on the first
 * call. */
int ws_view_targets_line(ws_view_targets *t, int split, int view, const float **out, ws_status *st);

/* From now on, line targets are made with the support of e (its hull's
 * contours and creases, line_evidence.h; e must outlive t): a fit sets it
 * once its hull is carved, before anyone asks for a line target. */
void ws_view_targets_set_evidence(ws_view_targets *t, const ws_line_evidence *e);

/* From now on, every view's silhouette and line target (where the view has
 * no edge map of the user's) are c's (edge_consensus.h; c must outlive t),
 * in place of its photo's and mask's: a fit sets it where the train views
 * have no usable silhouette or the user gives a box, before the hull is
 * carved. Whatever was made before is dropped. The hull's support
 * (ws_view_targets_set_evidence) is not read then: the consensus already
 * keeps only what the views agree on. */
void ws_view_targets_set_consensus(ws_view_targets *t, const ws_edge_consensus *c);

/* Frees what only a fit's setup reads when its loss reads no line target
 * (CLIP alone): every line target (the respawn keeps their edges in its
 * own form) and the validation and test views' silhouettes (the scene
 * check's): 36 MB for the rose. A later request makes them again. */
void ws_view_targets_release_setup(ws_view_targets *t);

#endif
