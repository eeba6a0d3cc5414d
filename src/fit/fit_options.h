/* fit_options.h: the settings of `wiresketch fit` (METHOD.md sections 5-7),
 * read by the loop, the checkpoint's command line and the outputs. */
#ifndef WS_FIT_OPTIONS_H
#define WS_FIT_OPTIONS_H
#include <stdint.h>
#include "nn/base/status.h"
#include "objective/loss.h"

struct ws_report_item;

typedef struct {
    const char *scene_dir;
    const char *out_dir;
    const char *init_curves;   /* "hull" (on the visual hull, the default), "edges" (on the
                                  photos' edges), "random" (METHOD.md section 2) or a curve
                                  file (fit/init.h) */
    int no_check;              /* skip the scene check (geometry/check.h) before a new fit */
    ws_loss_options loss;
    int size;                  /* working resolution (the model's with CLIP) */
    int batch_size, inner_steps, eval_every, threads;
    int n_curves;              /* curves, or WS_FIT_CURVES_AUTO (ws_fit_n_curves) */
    int epochs;                /* passes over the train views, or WS_FIT_EPOCHS_AUTO (ws_fit_epochs) */
    double learning_rate, thickness, radius, length, overlap, cutoff;
    uint64_t seed;
    int max_steps;             /* stop after this many steps in all (0: no limit) */
    double checkpoint_minutes; /* checkpoint at least this often */
    int snapshot_every;        /* steps between frames of evolution.gif */
    int respawn_every;         /* steps between moves of idle curves (fit/respawn.h); 0: never */
    int quiet;                 /* no progress line */
    float background[3];       /* the photos' background (scene.h) [black] */
    int background_auto;       /* 1: each image's border median instead */
    const char *edge_maps;     /* NULL, or the directory of the views' edge maps (scene.h) */
    const char *images;        /* NULL, or a COLMAP scene's images folder (scene.h) */
    const char *masks;         /* NULL, or the views' masks folder (scene.h) */
    const char *bbox;          /* NULL, or the region of interest "x0,y0,z0,x1,y1,z1" (geometry/roi.h) */
    /* report.html's settings table: every option of the run with its value
     * (the command line derives it from its option list); NULL: none */
    const struct ws_report_item *settings;
    int n_settings;
} ws_fit_options;

/* --epochs auto (the line loss's default): WS_FIT_AUTO_EPOCHS passes over
 * up to WS_FIT_AUTO_VIEWS train views, and past that as many as keep about
 * the steps of WS_FIT_AUTO_VIEWS views (rounded up): a capture of 200
 * photos runs 12 epochs, not 24. Its views lie closer together, so that
 * one pass shows each line about as often as two over 96; the curves need
 * steps, not passes (docs/RESULTS.md, "A capture of 200 views: the steps
 * of 96 views"). */
#define WS_FIT_EPOCHS_AUTO (-1)
#define WS_FIT_AUTO_EPOCHS 24
#define WS_FIT_AUTO_VIEWS 96

/* --n-curves auto (the default): WS_FIT_CURVES curves, or
 * WS_FIT_CURVES_SOLID where the fit draws the edges the views agree on and
 * the photos' colours carve a solid (objective/edge_consensus.h: `solid`).
 * A solid's edges are short straight lines, a curve each, and its outline
 * takes more: 25 curves left edges of the capture bed's nut (18 straight
 * edges and two rims) and dodecahedron (30 edges) undrawn. A wire's few long
 * curves are drawn by 25, and more settle off the wire (docs/RESULTS.md,
 * "Curves for a solid's edges"). */
#define WS_FIT_CURVES_AUTO (-1)
#define WS_FIT_CURVES 25
#define WS_FIT_CURVES_SOLID 35

void ws_fit_options_default(ws_fit_options *opt);
/* The curves a fit draws: opt->n_curves, or the rule above when it is
 * WS_FIT_CURVES_AUTO; solid: whether the fit's consensus found a solid. */
int ws_fit_n_curves(const ws_fit_options *opt, int solid);
/* The epochs a fit of ntrain train views runs: opt->epochs, or the rule
 * above when it is WS_FIT_EPOCHS_AUTO. */
int ws_fit_epochs(const ws_fit_options *opt, int ntrain);
/* Every option in its range (WS_EUSAGE naming the option otherwise); the
 * command line and a checkpoint's stored arguments both pass here. */
int ws_fit_options_check(const ws_fit_options *opt, ws_status *st);

#endif
