/* bench.h: the measurements behind `wiresketch bench` (METHOD.md section 7,
 * "report error against run time"). Each function measures; the command
 * line prints. Timings are the best of `rounds` repetitions (a busy machine
 * only ever slows a run down), and every comparison of two settings runs
 * both in alternation on the same inputs, so that a ratio holds even when
 * the machine is shared. Nothing here is a test: no threshold is checked.
 *
 * The inputs: a scene's cameras and photos (the benchmark uses
 * ../shared/scenes/rose), a sketch of random bent curves around the scene
 * centre (ws_bench_sketch) and a CLIP model (a full-size ViT-B/32 with
 * seeded random weights unless a weight file is given: the timings are
 * those of the real model; loss values are meaningless, their errors are
 * not). */
#ifndef WS_BENCH_H
#define WS_BENCH_H
#include <stddef.h>
#include "nn/clip.h"
#include "render/curves.h"
#include "io/scene.h"
#include "objective/objective.h"

/* n curves, bent and about `length` long, scattered within `radius` of
 * center, with the defaults' thickness and overlap (about length / 0.016
 * Gaussians each). Deterministic for a seed. Allocates c. */
int ws_bench_sketch(ws_curves *c, int n, const double center[3], double radius, double length,
                    uint64_t seed, ws_status *st);

/* out = c scaled by `scale` about center (1: a copy). Allocates out. */
int ws_bench_scaled(const ws_curves *c, double scale, const double center[3], ws_curves *out,
                    ws_status *st);

/* The (Gaussian, pixel) pairs splatting visits for n centres mu of world
 * radius r seen by cam: each cut-off box clipped to the image (every pixel
 * for the exact sum); *drawn: the Gaussians whose box meets the image. */
double ws_bench_pixel_visits(const ws_camera *cam, const double *mu, int n, double radius,
                             double cutoff, int *drawn);

/* ---- splatting: cost and error of the cut-off ---------------------------- */

enum { WS_BENCH_CUTOFFS = 5 };
/* 2, 3, 4, 5 sigma and INFINITY (the exact sum, the reference). */
extern const double ws_bench_cutoffs[WS_BENCH_CUTOFFS];

typedef struct {
    int gaussians;
    double pixel_visits[WS_BENCH_CUTOFFS]; /* (Gaussian, pixel) pairs inside the cut-off boxes */
    double forward[WS_BENCH_CUTOFFS], backward[WS_BENCH_CUTOFFS]; /* seconds */
    /* against the exact sum: |alpha - alpha_exact| over the pixels (max,
     * mean), and |dmu - dmu_exact| relative to max |dmu_exact| (max) and
     * to mean |dmu_exact| (mean), for a fixed random dL/dalpha */
    double alpha_max[WS_BENCH_CUTOFFS], alpha_mean[WS_BENCH_CUTOFFS];
    double grad_max[WS_BENCH_CUTOFFS], grad_mean[WS_BENCH_CUTOFFS];
} ws_bench_splat_row;

/* `gaussians` Gaussians of a random sketch around center, seen by cam. */
int ws_bench_splat(const ws_camera *cam, const double center[3], int gaussians, int rounds,
                   ws_bench_splat_row *row, ws_status *st);

/* ---- one training step: where the time goes ----------------------------- */

typedef struct {
    int gaussians, curves, views, num_aug, threads;
    ws_step_timing best;        /* the parts of the fastest step */
    double floor;               /* GEMM floor of the step's CLIP work, seconds */
    double floor_forward, floor_backward, floor_photo; /* its three parts */
} ws_bench_step_result;

/* The default step (METHOD.md section 7: one view, A = 4, cut-off 4) on
 * training view 0 of the scene for the sketch c, CLIP model m, after one
 * unmeasured step (the view's photo features cached, as in a fit). */
int ws_bench_step(const ws_scene *scene, const clip_model *m, const ws_curves *c, int rounds,
                  ws_bench_step_result *res, ws_status *st);

/* ---- error against run time of every approximation ---------------------- */

typedef struct {
    char name[64];          /* "cutoff", "clip_stop", ...: stable key */
    char setting[64];       /* "4 sigma", ... */
    char exact[64];         /* what it is compared with */
    char part[32];          /* the part of the step it changes */
    double loss_error;      /* |L - L_exact| / |L_exact|; NAN: not measured (see note) */
    double grad_error;      /* |g - g_exact| / |g_exact| (2-norms over all control points) */
    double part_exact, part_approx; /* seconds of that part */
    double step_exact, step_approx; /* seconds of the whole step */
    double bytes;           /* memory it needs, where that is its cost (else 0) */
    char note[160];
} ws_bench_approx_row;

typedef struct {
    const ws_scene *scene;
    const clip_model *model;      /* random or loaded f32 weights */
    const char *weights_f32;      /* the same seeded weights as f32 and f16 files */
    const char *weights_f16;      /*   (the f16 row is left out when either is NULL) */
    const ws_curves *sketch;
    int rounds;
    int aug_bank;                 /* N of the bank row */
    const clip_model *model_bf16; /* model's weights with bf16 GEMMs (clip.h), or NULL: no bf16 rows */
} ws_bench_approx_input;

/* Fills rows[0..*nrows) (at most max rows). */
int ws_bench_approx(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *nrows,
                    ws_status *st);

/* ---- the augmentation bank: how far its fixed transforms move a gradient -- */

typedef struct {
    const ws_scene *scene;
    const clip_model *model;
    const ws_curves *sketch;
    int steps;          /* steps of each setting (other draws of the step's generator) */
} ws_bench_bank_input;

typedef struct {
    /* the setting (filled by the caller) */
    int bank;           /* N transforms per view */
    uint64_t aug_seed;  /* which N */
    int against;        /* the row it is compared with, -1: fresh transforms */
    /* the measurement, relative to |mean gradient with fresh transforms| (2-norms
     * over all control points of training view 0's default loss) */
    int num_aug, steps;
    double difference;       /* |mean gradient - the other's mean gradient| */
    double difference_noise; /* what the two means' own sampling noise gives that difference */
    double bias;             /* sqrt(difference^2 - difference_noise^2): the bank's own */
    double predicted;        /* sqrt(A / N) x fresh_step_noise (x sqrt 2 between two banks) */
    double fresh_step_noise; /* one fresh step's spread around the mean */
    double loss_difference;  /* |mean loss - the other's| / |the other's| */
} ws_bench_bank_row;

/* Fills the measurement of rows[0..nrows) (their settings given). */
int ws_bench_bank(const ws_bench_bank_input *in, ws_bench_bank_row *rows, int nrows, ws_status *st);

#endif
