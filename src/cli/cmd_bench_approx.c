/* cmd_bench_approx.c: `wiresketch bench approx`: the error-against-run-time
 * table of every approximation that buys speed (bench/bench.h). */
#include <math.h>
#include <stdio.h>
#include <unistd.h>
#include "cli/cli_bench.h"

enum { MAX_ROWS = 32 };

/* "1.2e-03", "0" for an exact 0, "-" for not defined. */
static void error_text(double e, char text[16]) {
    if (!isfinite(e))
        snprintf(text, 16, "-");
    else if (e == 0)
        snprintf(text, 16, "0");
    else
        snprintf(text, 16, "%.1e", e);
}

int ws_cli_bench_approx(ws_cli_bench *ctx, cJSON *out, ws_status *st) {
    if (ws_cli_bench_scene(ctx, st) || ws_cli_bench_model(ctx, st) || ws_cli_bench_sketch(ctx, st)) return st->code;
    int pair = access(ctx->weights_f32, R_OK) == 0 && access(ctx->weights_f16, R_OK) == 0;
    const clip_model *mb = NULL;
    if (ctx->precision == CLIP_BF16 && ws_cli_bench_model_of(ctx, CLIP_BF16, &mb, st)) return st->code;
    ws_bench_approx_input in = {&ctx->scene, ctx->model, pair ? ctx->weights_f32 : NULL,
                                pair ? ctx->weights_f16 : NULL, &ctx->sketch, ctx->rounds, ctx->aug_bank, mb};
    ws_bench_approx_row rows[MAX_ROWS];
    int n;
    if (ws_bench_approx(&in, rows, MAX_ROWS, &n, st)) return st->code;
    cJSON *j = cJSON_AddArrayToObject(out, "approx");
    for (int i = 0; i < n; i++) {
        const ws_bench_approx_row *r = &rows[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", r->name);
        cJSON_AddStringToObject(o, "setting", r->setting);
        cJSON_AddStringToObject(o, "exact", r->exact);
        cJSON_AddStringToObject(o, "part", r->part);
        ws_cli_bench_add(o, "loss_error", r->loss_error);
        ws_cli_bench_add(o, "grad_error", r->grad_error);
        ws_cli_bench_add(o, "part_exact", r->part_exact);
        ws_cli_bench_add(o, "part_approx", r->part_approx);
        ws_cli_bench_add(o, "step_exact", r->step_exact);
        ws_cli_bench_add(o, "step_approx", r->step_approx);
        ws_cli_bench_add(o, "speedup", r->step_exact / r->step_approx);
        ws_cli_bench_add(o, "bytes", r->bytes);
        cJSON_AddStringToObject(o, "note", r->note);
        cJSON_AddItemToArray(j, o);
    }
    if (ctx->json) return WS_OK;
    printf("\n## Error against run time\n\n");
    printf("one training step of the default loss (CLIP ViT-B/32, %s weights: the errors are real, the "
           "loss values are not) on %s, training view 0, the same %d curves and the same transforms for "
           "both settings of a row; errors relative: |L - L_exact| / |L_exact| and "
           "|g - g_exact| / |g_exact| over all control points; times the fastest of %d runs of each, "
           "run in alternation\n\n",
           ctx->weights ? ctx->weights : "random", ctx->scene_dir, ctx->sketch.n, ctx->rounds);
    printf("| approximation | against | loss error | gradient error | part | part (ms) | step (ms) | "
           "step speed-up | notes |\n| --- | --- | ---: | ---: | --- | ---: | ---: | ---: | --- |\n");
    for (int i = 0; i < n; i++) {
        const ws_bench_approx_row *r = &rows[i];
        char le[16], ge[16], note[256];
        error_text(r->loss_error, le);
        error_text(r->grad_error, ge);
        if (r->bytes > 0)
            snprintf(note, sizeof note, "needs %.0f MB; %s", r->bytes / 1e6, r->note);
        else
            snprintf(note, sizeof note, "%s", r->note);
        printf("| %s: %s | %s | %s | %s | %s | %.1f -> %.1f | %.0f -> %.0f | %.2fx | %s |\n", r->name,
               r->setting, r->exact, le, ge, r->part, 1e3 * r->part_exact, 1e3 * r->part_approx,
               1e3 * r->step_exact, 1e3 * r->step_approx, r->step_exact / r->step_approx, note);
    }
    if (!pair)
        printf("\n(no f16 row: %s and %s are made by `make bench` with tools/make_random_weights.py)\n",
               ctx->weights_f32, ctx->weights_f16);
    return WS_OK;
}
