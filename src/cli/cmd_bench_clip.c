/* cmd_bench_clip.c: `wiresketch bench clip`: forward and forward+backward
 * time of CLIP's image tower against its GEMM floor (bench/clip_bench.h), by
 * default on a full-size ViT-B/32 with random weights, for the batch of a
 * default step (the unaugmented stroke image and 4 augmentations). */
#include <stdio.h>
#include "cli/cli_bench.h"
#include "bench/clip_bench.h"

/* Where the time goes, op by op, against the GEMM floor: matmul includes
 * its GEMMs, so its excess over the floor is the share of its biases
 * (in fp32; in bf16 matmul is its own kernel against fp32's floor). */
static void print_ops(const ws_clip_bench_result *r, const char *precision) {
    double floor = r->floor_forward_backward;
    printf("\n| op (%s) | forward (ms) | backward (ms) | share of the GEMM floor |\n"
           "| --- | ---: | ---: | ---: |\n", precision);
    for (int k = 0; k < NN_OP_KINDS; k++) {
        double f = r->op_forward[k], b = r->op_backward[k];
        if (f + b > 0)
            printf("| %s | %.1f | %.1f | %.3f |\n", nn_op_kind_name(k), 1e3 * f, 1e3 * b, (f + b) / floor);
    }
}

/* One precision's timings into j. */
static void add_json(cJSON *j, const ws_clip_bench_result *r) {
    ws_cli_bench_add(j, "forward", r->forward);
    ws_cli_bench_add(j, "forward_backward", r->forward_backward);
    ws_cli_bench_add(j, "floor_forward", r->floor_forward);
    ws_cli_bench_add(j, "floor_forward_backward", r->floor_forward_backward);
    ws_cli_bench_add(j, "ratio_forward", r->forward / r->floor_forward);
    ws_cli_bench_add(j, "ratio_forward_backward", r->forward_backward / r->floor_forward_backward);
    ws_cli_bench_add(j, "floor_forward_backward_openblas", r->floor_openblas);
    ws_cli_bench_add(j, "arena_bytes", (double)r->arena_bytes);
    cJSON *ops = cJSON_AddObjectToObject(j, "ops");
    for (int k = 0; k < NN_OP_KINDS; k++) {
        if (r->op_forward[k] + r->op_backward[k] <= 0) continue;
        cJSON *o = cJSON_AddObjectToObject(ops, nn_op_kind_name(k));
        ws_cli_bench_add(o, "forward", r->op_forward[k]);
        ws_cli_bench_add(o, "backward", r->op_backward[k]);
    }
}

static void print_rows(const ws_clip_bench_result *r, const char *precision) {
    printf("| forward (%s) | %.1f | %.1f | %.2f |\n", precision, 1e3 * r->forward, 1e3 * r->floor_forward,
           r->forward / r->floor_forward);
    printf("| forward+backward (%s) | %.1f | %.1f | %.2f |\n", precision, 1e3 * r->forward_backward,
           1e3 * r->floor_forward_backward, r->forward_backward / r->floor_forward_backward);
}

/* The tower in fp32, then with --precision bf16 (or auto on a CPU with
 * AVX512_BF16) in bf16 too: both against the same fp32 floor, each
 * measured in its own rounds. */
int ws_cli_bench_clip(ws_cli_bench *ctx, cJSON *out, ws_status *st) {
    ws_clip_bench_result r, rb;
    const clip_model *mb = NULL;
    int bf16 = ctx->precision == CLIP_BF16;
    if (ws_cli_bench_model(ctx, st) || ws_clip_bench_run(ctx->model, ctx->batch, ctx->rounds, &r, st) ||
        (bf16 && (ws_cli_bench_model_of(ctx, CLIP_BF16, &mb, st) ||
                  ws_clip_bench_run(mb, ctx->batch, ctx->rounds, &rb, st))))
        return st->code;
    const wf_arch *a = clip_model_arch(ctx->model);
    cJSON *j = cJSON_AddObjectToObject(out, "clip");
    cJSON_AddStringToObject(j, "weights", ctx->weights ? ctx->weights : "random");
    ws_cli_bench_add(j, "batch", r.batch);
    ws_cli_bench_add(j, "threads", r.threads);
    add_json(j, &r);
    if (bf16) add_json(cJSON_AddObjectToObject(j, "bf16"), &rb);
    if (ctx->json) return WS_OK;
    printf("\n## CLIP image tower\n\n");
    printf("width %d, %d blocks, %d heads, patch %d, %d x %d, output %d (%s); batch %d, %d threads, "
           "OpenMP in nn ops %s; best of %d rounds; the floor is fp32's (cblas_sgemm) for both precisions\n\n",
           a->width, a->layers, a->heads, a->patch, a->resolution, a->resolution, a->output_dim,
           ctx->weights ? ctx->weights : "random weights", r.batch, r.threads, r.nn_parallel ? "on" : "off",
           r.rounds);
    printf("| pass | time (ms) | GEMM floor (ms) | ratio |\n| --- | ---: | ---: | ---: |\n");
    print_rows(&r, "fp32");
    if (bf16) print_rows(&rb, "bf16");
    printf("\nthe floor's GEMMs whole, one cblas_sgemm call each on OpenBLAS's own threads (other bits on other "
           "thread counts with some kernels), after the rounds: %.1f ms; the fixed blocks of nn/ take %.2fx that\n",
           1e3 * r.floor_openblas, r.floor_forward_backward / r.floor_openblas);
    printf("\nactivation arena %.1f MB\n", r.arena_bytes / 1e6);
    print_ops(&r, "fp32");
    if (bf16) print_ops(&rb, "bf16");
    return WS_OK;
}
