/* bench_parts.h: the parts of `wiresketch bench` (cmd_bench.c runs them).
 *
 * Each part measures through the library (nn/clip_bench.h, src/bench.h),
 * prints its table (Markdown, so that it pastes into the README) unless
 * JSON was asked for, and adds its results to one JSON object under its
 * own key. Inputs are made once and shared, so that every part of one run
 * measures the same scene, sketch and model. */
#ifndef WS_BENCH_PARTS_H
#define WS_BENCH_PARTS_H
#include <cJSON.h>
#include "bench.h"
#include "clip.h"

typedef struct {
    /* options */
    int json, threads, rounds, batch, aug_bank;
    const char *scene_dir;   /* the scene of the splat, step and approx parts */
    const char *weights;     /* CLIP weights of the timings (NULL: random ViT-B/32) */
    const char *weights_f32; /* the same random weights as f32 and f16 files: */
    const char *weights_f16; /*   the f16 row and the memory part (skipped if absent) */
    const char *exe;         /* this program, for the memory part's child fits */
    /* inputs, made when a part first needs them */
    ws_scene scene;
    int have_scene;
    clip_model *model;
    ws_curves sketch;
} bench_ctx;

/* The scene, the model and the sketch of 25 curves (about 2,000
 * Gaussians), made on first use. */
int bench_scene(bench_ctx *ctx, ws_status *st);
int bench_model(bench_ctx *ctx, ws_status *st);
int bench_sketch(bench_ctx *ctx, ws_status *st);

int bench_part_clip(bench_ctx *ctx, cJSON *out, ws_status *st);
int bench_part_splat(bench_ctx *ctx, cJSON *out, ws_status *st);
int bench_part_step(bench_ctx *ctx, cJSON *out, ws_status *st);
int bench_part_approx(bench_ctx *ctx, cJSON *out, ws_status *st);
int bench_part_memory(bench_ctx *ctx, cJSON *out, ws_status *st);

/* A JSON number, null when not finite (JSON has no NaN). */
cJSON *bench_number(double x);

#endif
