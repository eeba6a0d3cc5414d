/* loss.h: the loss of one view (METHOD.md section 6) and its gradient.
 *
 * Terms, each with its own weight (0 = off):
 * - CLIP geometric: conv_weight * sum_l layer_weights[l] * mean over items,
 *   tokens and channels of (h_l(S_a) - h_l(T_a))^2 (geometric = blocks), or
 *   mean over items, heads, query and key tokens of (P_l(S_a) - P_l(T_a))^2,
 *   P_l block l's attention probabilities (geometric = attention);
 * - CLIP fc: fc_weight * mean over items of (1 - cos(e(S_a), e(T_a)));
 * - CLIP global: global_weight * sum over a = 1..A of (1 - cos(e(S_a), e(T_0)));
 * - lines: lines_weight * the line-drawing loss (lines.h) of item 0 against
 *   the photo's thin edges (thin_edges.h), its level weights following the
 *   fit's progress (ws_loss_set_progress) in training and final (p = 1) in
 *   evaluation (augment = 0);
 * - edges: edges_weight * the former weight-free loss, Sobel edges compared
 *   in L2 (edges.h) of item 0 (`--loss sobel`);
 * - l2: l2_weight * mean over pixels and channels of (S_0 - T_0)^2.
 * S_a, T_a: the stroke image and the photo under augmentation a (a = 0:
 * none). One CLIP forward and backward per stroke image; the photo's
 * features are computed without a tape, item 0's once per view (cached).
 *
 * Items and passes: a training view's items a = 0..A (an evaluated view's
 * item 0 alone) go through CLIP in passes of G = pass_items consecutive
 * items (the last may hold fewer), each pass one batch of stroke images
 * and one of the photos under its items' transforms. A view's loss is the
 * sum over its items' losses in item order plus the weight-free terms, its
 * dL/dalpha the same sum of the items' gradients: a pass's results do not
 * depend on where or when it runs, which is what lets a fit spread the
 * passes over MPI ranks (objective.c) with the bits of one process. GEMMs
 * round each row differently with the number of rows, so G, not the ranks,
 * decides the bits: 1 + A (the default) is the fastest on one process.
 *
 * Augmentation bank (aug_bank = N > 0): each training view gets N fixed
 * transforms, transform k of view v drawn from a generator seeded by
 * (aug_seed, v, k), so a resumed run needs nothing stored; each step uses
 * A distinct ones of them, chosen with the run's generator. The photo's
 * features under the N transforms are computed the first time the view is
 * used (in batches of A, always the same, so the bits do not depend on
 * when) and kept: N x (features of one image) per training view. Other
 * splits draw fresh transforms. */
#ifndef WS_LOSS_H
#define WS_LOSS_H
#include <stddef.h>
#include <stdint.h>
#include "nn/base/rng.h"
#include "io/scene.h"
#include "nn/base/status.h"
#include "base/timing.h"
#include "objective/hidden_mode.h"

struct clip_model;
struct ws_scene_hull;
struct ws_view_targets;

#define WS_LOSS_MAX_LAYERS 64
#define WS_LOSS_MAX_AUG 64 /* augmentations per view and step at the most */
/* The largest weight of a term. Adam's step does not grow with the scale
 * of the loss, so a larger weight only matters against the other terms,
 * and 1e6 keeps the squared gradient Adam keeps far from overflowing (a
 * weight of 1e300 made it infinite, and the checkpoint unreadable). */
#define WS_LOSS_MAX_WEIGHT 1e6

/* What the CLIP geometric term compares (--clip-geometric). */
typedef enum { WS_GEOMETRIC_BLOCKS, WS_GEOMETRIC_ATTENTION } ws_geometric;

typedef struct {
    const char *weights_path;  /* CLIP weight file; needed when a CLIP term is on */
    double conv_weight;        /* clip_conv_loss */
    ws_geometric geometric;    /* block outputs h_l (default) or attention probabilities P_l */
    int n_layer_weights;
    double layer_weights[WS_LOSS_MAX_LAYERS]; /* clip_conv_layer_weights, block l */
    double fc_weight;          /* clip_fc_loss_weight */
    double global_weight;      /* clip_weight */
    double lines_weight;
    double edges_weight;
    double l2_weight;
    double silhouette_weight;  /* the training batch's silhouette term (objective.h) */
    ws_hidden_mode hidden_lines; /* the stroke images' hidden-line removal (objective.h) */
    const struct ws_scene_hull *hull; /* borrowed: the training views' hull for it; NULL: carved when needed */
    int num_aug;               /* A */
    int aug_bank;              /* N fixed transforms per training view (0: fresh every step) */
    int pass_items;            /* G: stroke images per CLIP pass, 1..1+A (0: 1 + A) */
    uint64_t aug_seed;         /* derives the banked transforms */
    const struct clip_model *model; /* borrowed; NULL: load weights_path */
    int precision;             /* clip_precision (nn/clip.h) of the model loaded from weights_path:
                                  CLIP_FP32 (the default) or CLIP_BF16; a borrowed model keeps its own */
    struct ws_view_targets *targets; /* the scene's silhouettes and line targets (view_targets.h),
                                        borrowed (a fit shares its own, made for the same scene);
                                        NULL: the loss makes its own */
} ws_loss_options;

/* The original's defaults: CLIP terms on, edges and l2 off, A = 4, no bank. */
void ws_loss_options_default(ws_loss_options *opt);
/* Does any CLIP term have a non-zero weight? */
int ws_loss_uses_clip(const ws_loss_options *opt);

typedef struct ws_loss ws_loss;

/* Every option in its range (WS_EUSAGE naming the option otherwise):
 * augmentation counts, the geometric variant, and term weights >= 0.
 * ws_loss_create checks too. */
int ws_loss_options_check(const ws_loss_options *opt, ws_status *st);
/* For the scene's views at its working resolution, which must equal the CLIP
 * model's input resolution when CLIP is used. */
int ws_loss_create(ws_loss **loss, const ws_loss_options *opt, const ws_scene *scene,
                   ws_status *st);
void ws_loss_free(ws_loss *loss);

/* The view targets it reads (its own or the borrowed ones): the objective's
 * silhouette term reads the same silhouettes. */
struct ws_view_targets *ws_loss_targets(const ws_loss *loss);

/* The fit's progress in [0, 1] (steps done / steps planned): sets the line
 * loss's coarse-to-fine level weights of training steps (lines.h). */
void ws_loss_set_progress(ws_loss *loss, double progress);

/* From now on add the time of augmentation and CLIP to t (NULL: stop). */
void ws_loss_set_timing(ws_loss *loss, ws_step_timing *t);
/* Bytes of the augmentation bank's photo features once every training view
 * has been used (0 without a bank): a view's are allocated when it is first
 * used, as are its cached photo features, edge map and line target. */
size_t ws_loss_bank_bytes(const ws_loss *loss);

/* A view's loss in parts (the items and passes above). items: 1 + A
 * (augment) or 1 with CLIP, 0 without; passes: at least 1 (without CLIP a
 * pass does nothing and the view is its own unit of work). */
int ws_loss_items(const ws_loss *loss, int augment);
int ws_loss_passes(const ws_loss *loss, int augment);
/* The items [first, first + count) of pass `pass`. */
void ws_loss_pass_items(const ws_loss *loss, int augment, int pass, int *first, int *count);
/* Draws the view's A transforms for this step from rng: once per training
 * view and step, in view order, before its passes. */
int ws_loss_draw(ws_loss *loss, int split, int view, ws_rng *rng, ws_status *st);
/* Pass `pass` for the stroke image alpha (H x W): item_loss (count) gets
 * each item's loss, item_grad (count x H x W, or NULL) its dL/dalpha. */
int ws_loss_pass(ws_loss *loss, int split, int view, const double *alpha, int augment, int pass,
                 double *item_loss, float *item_grad, ws_status *st);
/* The view's loss from every item's (item_loss: items; item_grad: items x
 * H x W, or NULL with dalpha NULL) and the weight-free terms; dalpha (H x
 * W, or NULL): overwritten with dL/dalpha. WS_ENUMERIC when not finite. */
int ws_loss_combine(ws_loss *loss, int split, int view, const double *alpha, int augment,
                    const double *item_loss, const float *item_grad, double *value, double *dalpha,
                    ws_status *st);

/* The loss of view `view` of `split` for the stroke image alpha (H x W).
 * augment: draw A transforms from rng (training); 0: item 0 only
 * (evaluation), rng unused. dalpha (H x W): overwritten with dL/dalpha, or
 * NULL for the loss alone. */
int ws_loss_view(ws_loss *loss, int split, int view, const double *alpha, int augment,
                 ws_rng *rng, double *value, double *dalpha, ws_status *st);

#endif
