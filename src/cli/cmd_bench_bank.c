/* cmd_bench_bank.c: `wiresketch bench bank`: how far the augmentation
 * bank's fixed transforms move a view's expected gradient, against the
 * noise of fresh transforms (bench/bench.h). */
#include <math.h>
#include <stdio.h>
#include "cli/cli_bench.h"

/* Steps per setting: the mean of 24 steps carries 1/sqrt(24) = 0.2 of one
 * step's noise, well below the bias of a bank of 8 (0.7 of it). */
enum { BANK_STEPS = 24 };

int ws_cli_bench_bank(ws_cli_bench *ctx, cJSON *out, ws_status *st) {
    const clip_model *m;
    if (ws_cli_bench_scene(ctx, st) || ws_cli_bench_model_of(ctx, ctx->precision, &m, st) ||
        ws_cli_bench_sketch(ctx, st))
        return st->code;
    int N = ctx->aug_bank;
    /* a bank of N (two seeds: two banks), one of 4N, and the two banks of N against each other */
    ws_bench_bank_row rows[] = {{.bank = N, .aug_seed = 5, .against = -1},
                                {.bank = N, .aug_seed = 6, .against = -1},
                                {.bank = 4 * N, .aug_seed = 5, .against = -1},
                                {.bank = N, .aug_seed = 6, .against = 0}};
    enum { NROWS = sizeof rows / sizeof rows[0] };
    ws_bench_bank_input in = {&ctx->scene, m, &ctx->sketch, BANK_STEPS};
    if (ws_bench_bank(&in, rows, NROWS, st)) return st->code;
    cJSON *j = cJSON_AddArrayToObject(out, "bank");
    for (int r = 0; r < NROWS; r++) {
        const ws_bench_bank_row *w = &rows[r];
        cJSON *o = cJSON_CreateObject();
        ws_cli_bench_add(o, "bank", w->bank);
        ws_cli_bench_add(o, "aug_seed", (double)w->aug_seed);
        ws_cli_bench_add(o, "against_row", w->against);
        ws_cli_bench_add(o, "num_aug", w->num_aug);
        ws_cli_bench_add(o, "steps", w->steps);
        ws_cli_bench_add(o, "difference", w->difference);
        ws_cli_bench_add(o, "difference_noise", w->difference_noise);
        ws_cli_bench_add(o, "bias", w->bias);
        ws_cli_bench_add(o, "predicted", w->predicted);
        ws_cli_bench_add(o, "fresh_step_noise", w->fresh_step_noise);
        ws_cli_bench_add(o, "loss_difference", w->loss_difference);
        cJSON_AddItemToArray(j, o);
    }
    if (ctx->json) return WS_OK;
    printf("\n## The augmentation bank against fresh transforms\n\n");
    printf("%s, training view 0, %d curves, the default CLIP loss (%s weights), A = %d, CLIP's weight GEMMs in "
           "%s; each setting's mean gradient over %d steps (other draws); all relative to |mean gradient with "
           "fresh transforms|; one fresh step's noise around it: %.3f\n\n",
           ctx->scene_dir, ctx->sketch.n, ctx->weights ? ctx->weights : "random", rows[0].num_aug,
           ctx->precision == CLIP_BF16 ? "bf16" : "fp32", BANK_STEPS, rows[0].fresh_step_noise);
    printf("| bank | against | mean gradient difference | of it the means' own noise | the bank's bias | "
           "predicted sqrt(A/N) x step noise | mean loss difference |\n"
           "| --- | --- | ---: | ---: | ---: | ---: | ---: |\n");
    for (int r = 0; r < NROWS; r++) {
        const ws_bench_bank_row *w = &rows[r];
        char against[64];
        if (w->against < 0)
            snprintf(against, sizeof against, "fresh transforms");
        else
            snprintf(against, sizeof against, "N = %d, seed %llu", rows[w->against].bank,
                     (unsigned long long)rows[w->against].aug_seed);
        printf("| N = %d, seed %llu | %s | %.3f | %.3f | %.3f | %.3f | %.1e |\n", w->bank,
               (unsigned long long)w->aug_seed, against, w->difference, w->difference_noise, w->bias,
               w->predicted, w->loss_difference);
    }
    printf("\nA fresh fit's average over S steps on a view keeps %.3f / sqrt(S) of noise; a bank's bias "
           "stays: a bank of N = %d matches it at S = %.0f steps per view\n",
           rows[0].fresh_step_noise, N,
           rows[0].bias > 0 ? pow(rows[0].fresh_step_noise / rows[0].bias, 2) : INFINITY);
    return WS_OK;
}
