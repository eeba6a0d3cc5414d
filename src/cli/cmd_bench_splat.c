/* cmd_bench_splat.c: `wiresketch bench splat`: splatting forward and
 * backward for 1k, 10k and 100k Gaussians at each cut-off, time and error
 * against the exact sum (bench/bench.h). */
#include <math.h>
#include <stdio.h>
#include "cli/cli_bench.h"

int ws_cli_bench_splat(ws_cli_bench *ctx, cJSON *out, ws_status *st) {
    static const int counts[] = {1000, 10000, 100000};
    if (ws_cli_bench_scene(ctx, st)) return st->code;
    const ws_camera *cam = &ctx->scene.split[WS_TRAIN].views[0].cam;
    cJSON *j = cJSON_AddArrayToObject(out, "splat");
    if (!ctx->json) {
        printf("\n## Splatting\n\n");
        printf("random bent curves within 0.8 of the centre of %s, training view 0 (%d x %d), "
               "thickness 0.02; forward and backward (a random dL/dalpha) best of %d rounds (the exact "
               "sum of 100k: one); errors against the exact sum: |alpha - exact| over the pixels, "
               "|dL/dmu - exact| relative to max |exact| (max) and to mean |exact| (mean)\n\n",
               ctx->scene_dir, cam->width, cam->height, ctx->rounds);
        printf("| Gaussians | cut-off | pixel visits | forward (ms) | backward (ms) | alpha max err | "
               "alpha mean err | grad max err | grad mean err |\n");
        printf("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    }
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        ws_bench_splat_row r;
        if (ws_bench_splat(cam, ctx->scene.center, counts[i], ctx->rounds, &r, st)) return st->code;
        for (int k = 0; k < WS_BENCH_CUTOFFS; k++) {
            double cut = ws_bench_cutoffs[k];
            cJSON *o = cJSON_CreateObject();
            ws_cli_bench_add(o, "gaussians", r.gaussians);
            if (isfinite(cut))
                ws_cli_bench_add(o, "cutoff", cut);
            else
                cJSON_AddStringToObject(o, "cutoff", "exact");
            ws_cli_bench_add(o, "pixel_visits", r.pixel_visits[k]);
            ws_cli_bench_add(o, "forward", r.forward[k]);
            ws_cli_bench_add(o, "backward", r.backward[k]);
            ws_cli_bench_add(o, "alpha_max_error", r.alpha_max[k]);
            ws_cli_bench_add(o, "alpha_mean_error", r.alpha_mean[k]);
            ws_cli_bench_add(o, "grad_max_error", r.grad_max[k]);
            ws_cli_bench_add(o, "grad_mean_error", r.grad_mean[k]);
            cJSON_AddItemToArray(j, o);
            if (ctx->json) continue;
            char cutoff[16];
            snprintf(cutoff, sizeof cutoff, isfinite(cut) ? "%g sigma" : "exact", cut);
            printf("| %d | %s | %.3g | %.2f | %.2f | %.1e | %.1e | %.1e | %.1e |\n", r.gaussians, cutoff,
                   r.pixel_visits[k], 1e3 * r.forward[k], 1e3 * r.backward[k], r.alpha_max[k],
                   r.alpha_mean[k], r.grad_max[k], r.grad_mean[k]);
        }
        fflush(stdout);
    }
    return WS_OK;
}
