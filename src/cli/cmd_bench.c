/* cmd_bench.c: `wiresketch bench [PART] [--json]`: the benchmarks, one part
 * per concern (cli_bench.h); without PART every part runs, in one process
 * on the same inputs. They print tables; nothing here is a test. */
#include <cblas.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli/args.h"
#include "cli/cli_rows.h"
#include "cli/cli_bench.h"
#include "cli/cli_loss.h"
#include "cli/commands.h"
#include "base/runtime.h"
#include "geometry/roi.h"

static const struct {
    const char *name;
    int (*run)(ws_cli_bench *ctx, cJSON *out, ws_status *st);
    const char *summary;
} parts[] = {
    {"clip", ws_cli_bench_clip, "CLIP forward and forward+backward against the GEMM floor"},
    {"splat", ws_cli_bench_splat, "splatting time and error for 1k, 10k, 100k Gaussians and each cut-off"},
    {"step", ws_cli_bench_step, "where the time of a default training step goes"},
    {"approx", ws_cli_bench_approx, "error against run time of every approximation"},
    {"memory", ws_cli_bench_memory, "peak memory of a default fit (a child process)"},
    {"bank", ws_cli_bench_bank, "how far the augmentation bank's fixed transforms move a view's gradient"},
};
enum { NPARTS = sizeof parts / sizeof parts[0] };

void ws_cli_bench_add(cJSON *o, const char *key, double x) {
    if (isfinite(x)) {
        cJSON_AddNumberToObject(o, key, x);
        return;
    }
    char why_key[128], why[96];
    snprintf(why_key, sizeof why_key, "%s_why", key);
    snprintf(why, sizeof why, "the value is %s, which JSON cannot hold", isnan(x) ? "nan" : x > 0 ? "inf" : "-inf");
    cJSON_AddNullToObject(o, key);
    cJSON_AddStringToObject(o, why_key, why);
}

int ws_cli_bench_scene(ws_cli_bench *ctx, ws_status *st) {
    if (ctx->have_scene) return WS_OK;
    ws_scene_options so;
    ws_scene_options_default(&so);
    if (ws_roi_load_scene(&ctx->scene, ctx->scene_dir, &so, NULL, NULL, NULL, st)) return st->code;
    ctx->have_scene = 1;
    return WS_OK;
}

/* The bench's weights: the file of --weights, or a random ViT-B/32. */
static int make_model(const ws_cli_bench *ctx, clip_model **m, ws_status *st) {
    static const wf_arch vit_b32 = {768, 12, 12, 32, 224, 512};
    return ctx->weights ? clip_model_load(m, ctx->weights, st) : clip_model_random(m, &vit_b32, 1, st);
}

int ws_cli_bench_model(ws_cli_bench *ctx, ws_status *st) {
    return ctx->model ? WS_OK : make_model(ctx, &ctx->model, st);
}

int ws_cli_bench_model_of(ws_cli_bench *ctx, int precision, const clip_model **m, ws_status *st) {
    if (precision == CLIP_FP32) {
        if (ws_cli_bench_model(ctx, st)) return st->code;
        *m = ctx->model;
        return WS_OK;
    }
    if (!ctx->model_bf16 && (make_model(ctx, &ctx->model_bf16, st) ||
                             clip_model_set_precision(ctx->model_bf16, CLIP_BF16, st)))
        return st->code;
    *m = ctx->model_bf16;
    return WS_OK;
}

int ws_cli_bench_sketch(ws_cli_bench *ctx, ws_status *st) {
    if (ctx->sketch.n) return WS_OK;
    /* 25 curves of ~1 unit around the centre: about 2,000 Gaussians, the
     * size a default fit's sketch grows to */
    return ws_cli_bench_scene(ctx, st) || ws_bench_sketch(&ctx->sketch, 25, ctx->scene.center, 0.8, 1.05, 1, st)
               ? st->code
               : WS_OK;
}

/* The machine: CPU model, cores, OpenBLAS build and kernels, load. */
static cJSON *machine(void) {
    char cpu[256] = "unknown", line[512];
    FILE *f = fopen("/proc/cpuinfo", "r");
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "model name", 10) && strchr(line, ':')) {
            snprintf(cpu, sizeof cpu, "%s", strchr(line, ':') + 2);
            cpu[strcspn(cpu, "\n")] = '\0';
            break;
        }
    if (f) fclose(f);
    double load[3] = {NAN, NAN, NAN};
    f = fopen("/proc/loadavg", "r");
    if (f && fscanf(f, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = NAN;
    if (f) fclose(f);
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "cpu", cpu);
    ws_cli_bench_add(m, "cores", omp_get_num_procs());
    ws_cli_bench_add(m, "threads", ws_runtime_threads());
    cJSON_AddStringToObject(m, "openblas", openblas_get_config());
    const ws_blas_kernels *k = ws_runtime_kernels();
    cJSON_AddStringToObject(m, "kernels", openblas_get_corename());
    cJSON_AddStringToObject(m, "kernels_openblas_chose", k->before);
    cJSON_AddStringToObject(m, "kernels_why", k->why);
    ws_cli_bench_add(m, "load_average", load[0]);
    return m;
}

static void free_ctx(ws_cli_bench *ctx) {
    if (ctx->have_scene) ws_scene_free(&ctx->scene);
    clip_model_free(ctx->model);
    clip_model_free(ctx->model_bf16);
    ws_curves_free(&ctx->sketch);
}

/* The results object with its "machine" entry, which the tables (unless
 * json) begin with as a line; NULL (WS_ENOMEM) when it cannot be made. */
static cJSON *results_start(int json, ws_status *st) {
    cJSON *out = cJSON_CreateObject(), *m = machine();
    /* the line below reads these two fields back: without them there is no result to fill */
    if (!out || !cJSON_GetObjectItem(m, "cpu") || !cJSON_GetObjectItem(m, "load_average") ||
        !cJSON_AddItemToObject(out, "machine", m)) {
        cJSON_Delete(out);
        cJSON_Delete(m);
        ws_fail(st, WS_ENOMEM, "bench: out of memory building the results");
        return NULL;
    }
    if (!json)
        printf("machine: %s, %d cores, %d threads; %s; kernels %s (OpenBLAS chose %s: %s); load average "
               "%.2f at the start\n",
               cJSON_GetObjectItem(m, "cpu")->valuestring, omp_get_num_procs(), ws_runtime_threads(),
               openblas_get_config(), openblas_get_corename(), ws_runtime_kernels()->before,
               ws_runtime_kernels()->why, cJSON_GetObjectItem(m, "load_average")->valuedouble);
    return out;
}

int cmd_bench(int argc, char **argv) {
    ws_cli_bench ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.rounds = 3;
    ctx.batch = 5;
    ctx.aug_bank = 8;
    ctx.scene_dir = "../shared/scenes/rose";
    ctx.weights_f32 = "weights/random-f32.bin";
    ctx.weights_f16 = "weights/random-f16.bin";
    ctx.exe = "/proc/self/exe";
    const char *precision = "auto";
    const ws_arg args[] = {
        {"--json", WS_ARG_FLAG, &ctx.json, 0, "one JSON object instead of tables"},
        WS_ROW_THREADS(&ctx.threads),
        {"--rounds", WS_ARG_INT, &ctx.rounds, 0, "timed rounds; the best counts [3]"},
        {"--batch", WS_ARG_INT, &ctx.batch, 0, "clip: images per pass [5, a default step's]"},
        {"--scene", WS_ARG_STRING, &ctx.scene_dir, 0, "scene of splat, step, approx, memory, bank [../shared/scenes/rose]"},
        {"--weights", WS_ARG_STRING, &ctx.weights, 0, "CLIP weights [none: ViT-B/32, random weights]"},
        {"--weights-f32", WS_ARG_STRING, &ctx.weights_f32, 0,
         "random weights as f32 (tools/make_random_weights.py) [weights/random-f32.bin]"},
        {"--weights-f16", WS_ARG_STRING, &ctx.weights_f16, 0, "the same as f16 [weights/random-f16.bin]"},
        {"--aug-bank", WS_ARG_INT, &ctx.aug_bank, 0, "approx and bank: transforms per view of the bank [8]"},
        WS_ROW_PRECISION(&precision),
    };
    const ws_command_spec spec = {
        "bench [clip|splat|step|approx|memory|bank] [options]",
        "Speed against the hardware's floor and error against run time; every part without PART.\n"
        "--precision applies to the step part and clip's second row.",
        args, sizeof args / sizeof args[0], 0, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done == 0) { /* --help: the usage was printed, the parts follow */
        printf("\nparts:\n");
        for (int i = 0; i < NPARTS; i++) printf("  %-8s %s\n", parts[i].name, parts[i].summary);
    }
    if (done != WS_CLI_GO_ON) return done;
    int only = -1;
    for (int i = 0; npos && i < NPARTS; i++)
        if (!strcmp(pos[0], parts[i].name)) only = i;
    if (npos && only < 0) {
        ws_fail(&st, WS_EUSAGE, "bench %s: unknown part (clip, splat, step, approx, memory or bank)", pos[0]);
        return ws_cli_fail(&st);
    }
    if (ctx.batch < 1 || ctx.threads < 0 || ctx.rounds < 1 || ctx.aug_bank < 4) {
        ws_fail(&st, WS_EUSAGE, "bench: --batch and --rounds must be at least 1, --threads at least 0, "
                                "--aug-bank at least 4");
        return ws_cli_fail(&st);
    }
    if (ws_cli_choose_precision(precision, &ctx.precision, &st) || ws_runtime_init(ctx.threads, &st))
        return ws_cli_fail(&st);
    cJSON *out = results_start(ctx.json, &st);
    if (!out) return ws_cli_fail(&st);
    int rc = WS_OK;
    for (int i = 0; i < NPARTS && !rc; i++)
        if (only < 0 || only == i) rc = parts[i].run(&ctx, out, &st);
    if (!rc && ctx.json) {
        char *text = cJSON_Print(out);
        if (text)
            printf("%s\n", text);
        else
            rc = ws_fail(&st, WS_ENOMEM, "bench: out of memory printing the results as JSON");
        free(text);
    }
    cJSON_Delete(out);
    free_ctx(&ctx);
    return rc ? ws_cli_fail(&st) : 0;
}
