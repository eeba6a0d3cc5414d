/* cli_bench.h: the parts of `wiresketch bench` (cmd_bench.c runs them).
 *
 * Each part measures through the library (bench/clip_bench.h, bench/bench.h),
 * prints its table (Markdown, so that it pastes into docs/RESULTS.md) unless
 * JSON was asked for, and adds its results to one JSON object under its
 * own key. Inputs are made once and shared, so that every part of one run
 * measures the same scene, sketch and model. */
#ifndef WS_CLI_BENCH_H
#define WS_CLI_BENCH_H
#include <cJSON.h>
#include "bench/bench.h"
#include "nn/clip.h"

typedef struct {
    /* options */
    int json, threads, rounds, batch, aug_bank;
    const char *scene_dir;   /* the scene of the splat, step and approx parts */
    const char *weights;     /* CLIP weights of the timings (NULL: random ViT-B/32) */
    const char *weights_f32; /* the same random weights as f32 and f16 files: */
    const char *weights_f16; /*   the f16 row and the memory part (skipped if absent) */
    const char *exe;         /* this program, for the memory part's child fits */
    int precision;           /* clip_precision of the step part and the clip part's second row */
    /* inputs, made when a part first needs them */
    ws_scene scene;
    int have_scene;
    clip_model *model;       /* fp32 */
    clip_model *model_bf16;  /* the same weights with bf16 GEMMs (clip.h), made when a part needs it */
    ws_curves sketch;
} ws_cli_bench;

/* The scene, the model and the sketch of 25 curves (about 2,000
 * Gaussians), made on first use. */
int ws_cli_bench_scene(ws_cli_bench *ctx, ws_status *st);
int ws_cli_bench_model(ws_cli_bench *ctx, ws_status *st);
/* The model of --precision: ctx->model, or ctx->model_bf16 made on first use. */
int ws_cli_bench_model_of(ws_cli_bench *ctx, int precision, const clip_model **m, ws_status *st);
int ws_cli_bench_sketch(ws_cli_bench *ctx, ws_status *st);

int ws_cli_bench_clip(ws_cli_bench *ctx, cJSON *out, ws_status *st);
int ws_cli_bench_splat(ws_cli_bench *ctx, cJSON *out, ws_status *st);
int ws_cli_bench_step(ws_cli_bench *ctx, cJSON *out, ws_status *st);
int ws_cli_bench_approx(ws_cli_bench *ctx, cJSON *out, ws_status *st);
int ws_cli_bench_memory(ws_cli_bench *ctx, cJSON *out, ws_status *st);
int ws_cli_bench_bank(ws_cli_bench *ctx, cJSON *out, ws_status *st);

/* A JSON number, null when not finite (JSON has no NaN). */
/* Adds KEY: x to o, or for a non-finite x KEY: null and beside it KEY_why,
 * the reason (JSON has no NaN or infinity; base/json_number.h). */
void ws_cli_bench_add(cJSON *o, const char *key, double x);

#endif
