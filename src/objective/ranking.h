/* ranking.h: what an objective must rank (docs/METHOD.md section 6, "Rankings"): the ground
 * truth against sketches that are worse in known ways, each scored as the
 * mean loss over the views of a split (item 0, no augmentation).
 *
 * With S the largest side of the ground truth's bounding box (ws_curves_bbox)
 * and c its centre, the variants of a ground-truth curve set are:
 *   WS_RANK_TRUTH   the ground truth;
 *   WS_RANK_EMPTY   no curves (the stroke image is 0);
 *   WS_RANK_DOT     one curve whose control points are all c;
 *   WS_RANK_DOTS    every curve shrunk to the point at its t = 1/2;
 *   WS_RANK_HALF    the curves of even index;
 *   WS_RANK_SHIFT1  every control point moved by 0.01 S along u;
 *   WS_RANK_SHIFT5  by 0.05 S along u (u = (1, 2, 3) / sqrt(14));
 *   WS_RANK_NOISE   the ground truth and 10 random straight strokes of
 *                   length 0.3 S, centred uniformly in the box, in
 *                   uniform directions (seeded).
 * All variants get the given thickness. */
#ifndef WS_RANKING_H
#define WS_RANKING_H
#include <stdint.h>
#include "objective/objective.h"
#include "render/curves.h"

enum {
    WS_RANK_TRUTH,
    WS_RANK_EMPTY,
    WS_RANK_DOT,
    WS_RANK_DOTS,
    WS_RANK_HALF,
    WS_RANK_SHIFT1,
    WS_RANK_SHIFT5,
    WS_RANK_NOISE,
    WS_RANK_COUNT
};
extern const char *const ws_rank_names[WS_RANK_COUNT];


/* The most curves a variant of gt has: an objective that scores them
 * must take that many (ws_objective_create). */
int ws_rank_curves(const ws_curves *gt);

/* loss[k] = the mean loss over `split` of variant k, k < WS_RANK_COUNT,
 * scored by obj (ws_objective_split_mean: its loss, splatting and
 * hidden-line removal); an empty split is an error. */
int ws_rank_losses(ws_objective *obj, int split, const ws_curves *gt, double thickness, uint64_t seed,
                   double loss_out[WS_RANK_COUNT], ws_status *st);

/* *out = the mean loss over `split` of c, drawn at its own thickness (a
 * sketch of the caller's, e.g. tests/test_rank.c's two outlines of a tube),
 * scored as above. */
int ws_rank_score(ws_objective *obj, int split, const ws_curves *c, double *out, ws_status *st);

#endif
