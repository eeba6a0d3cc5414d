/* cmd_bench_step.c: `wiresketch bench step`: where the time of one default
 * training step goes, against the GEMM floor of its CLIP work (bench/bench.h). */
#include <stdio.h>
#include "cli/cli_bench.h"

int ws_cli_bench_step(ws_cli_bench *ctx, cJSON *out, ws_status *st) {
    ws_bench_step_result r;
    const clip_model *m;
    if (ws_cli_bench_scene(ctx, st) || ws_cli_bench_model_of(ctx, ctx->precision, &m, st) ||
        ws_cli_bench_sketch(ctx, st) || ws_bench_step(&ctx->scene, m, &ctx->sketch, ctx->rounds, &r, st))
        return st->code;
    const char *precision = ctx->precision == CLIP_BF16 ? "bf16" : "fp32";
    const double *t = r.best.seconds, total = t[WS_TIME_TOTAL];
    double named = 0;
    for (int k = 0; k < WS_TIME_TOTAL; k++) named += t[k];
    double other = total - named;
    double clip = t[WS_TIME_CLIP_FORWARD] + t[WS_TIME_CLIP_PHOTO] + t[WS_TIME_CLIP_BACKWARD];
    cJSON *j = cJSON_AddObjectToObject(out, "step");
    ws_cli_bench_add(j, "gaussians", r.gaussians);
    ws_cli_bench_add(j, "curves", r.curves);
    ws_cli_bench_add(j, "num_aug", r.num_aug);
    ws_cli_bench_add(j, "threads", r.threads);
    cJSON_AddStringToObject(j, "precision", precision);
    cJSON *parts = cJSON_AddObjectToObject(j, "seconds");
    for (int k = 0; k < WS_TIME_PARTS; k++) ws_cli_bench_add(parts, ws_time_names[k], t[k]);
    ws_cli_bench_add(parts, "other", other);
    ws_cli_bench_add(j, "floor", r.floor);
    ws_cli_bench_add(j, "floor_forward", r.floor_forward);
    ws_cli_bench_add(j, "floor_backward", r.floor_backward);
    ws_cli_bench_add(j, "floor_photo", r.floor_photo);
    ws_cli_bench_add(j, "ratio", total / r.floor);
    ws_cli_bench_add(j, "non_clip_share", (total - clip) / total);
    if (ctx->json) return WS_OK;
    printf("\n## One default training step\n\n");
    printf("%s, training view 0, %d curves (%d Gaussians), %d augmentations, cut-off 4, %d threads, CLIP's "
           "weight GEMMs in %s (the floor: fp32's); the fastest of %d steps (after one that caches the view's "
           "photo features)\n\n",
           ctx->scene_dir, r.curves, r.gaussians, r.num_aug, r.threads, precision, ctx->rounds);
    static const char *const label[WS_TIME_PARTS] = {
        "splatting (forward + backward)", "augmentation (forward + backward)",
        "CLIP forward, 5 stroke images", "CLIP forward, 4 augmented photos", "CLIP backward, 5 stroke images",
        "optimiser (Adam)", "total"};
    printf("| part | ms | share |\n| --- | ---: | ---: |\n");
    for (int k = 0; k < WS_TIME_TOTAL; k++)
        printf("| %s | %.1f | %.1f%% |\n", label[k], 1e3 * t[k], 100 * t[k] / total);
    printf("| other (sampling, loss terms, copies) | %.1f | %.1f%% |\n", 1e3 * other, 100 * other / total);
    printf("| **step** | **%.1f** | |\n", 1e3 * total);
    printf("\nGEMM floor of its CLIP work %.1f ms (stroke forward %.1f, stroke backward %.1f, photo "
           "forward %.1f): step / floor = **%.2f**; everything but CLIP: %.1f%% of the step\n",
           1e3 * r.floor, 1e3 * r.floor_forward, 1e3 * r.floor_backward, 1e3 * r.floor_photo,
           total / r.floor, 100 * (total - clip) / total);
    return WS_OK;
}
