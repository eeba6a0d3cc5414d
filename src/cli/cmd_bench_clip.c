/* cmd_bench_clip.c: `wiresketch bench clip`: forward and forward+backward
 * time of CLIP's image tower against its GEMM floor (clip_bench.h), by
 * default on a full-size ViT-B/32 with random weights. */
#include <stdio.h>
#include "args.h"
#include "clip_bench.h"
#include "commands.h"
#include "threads.h"

int cmd_bench_clip(int argc, char **argv) {
    const char *weights = NULL;
    int batch = 5, threads = 0, rounds = 5;
    const ws_arg args[] = {
        {"--batch", WS_ARG_INT, &batch, 0, "images per pass [5]"},
        {"--threads", WS_ARG_INT, &threads, 0, "threads, 0 = one per core [0]"},
        {"--rounds", WS_ARG_INT, &rounds, 0, "timed rounds; the best counts [5]"},
        {"--weights", WS_ARG_STRING, &weights, 0,
         "CLIP weight file [none: ViT-B/32 with random weights]"},
    };
    const ws_command_spec spec = {
        "bench clip [--batch N] [--threads N] [--rounds N] [--weights FILE]",
        "Time CLIP's image tower, forward and forward+backward, against its GEMMs alone.",
        args, sizeof args / sizeof args[0], 0, 0};
    int npos, help;
    ws_status st;
    ws_status_clear(&st);
    if (ws_args_parse(&spec, argc, argv, NULL, &npos, &help, &st)) return ws_cli_fail(&st);
    if (help) return 0;
    if (batch < 1 || threads < 0 || rounds < 1) {
        ws_fail(&st, WS_EUSAGE, "--batch and --rounds must be at least 1, --threads at least 0");
        return ws_cli_fail(&st);
    }
    ws_threads_set(threads);
    clip_model *m = NULL;
    const wf_arch vit_b32 = {768, 12, 12, 32, 224, 512};
    if (weights ? clip_model_load(&m, weights, &st) : clip_model_random(&m, &vit_b32, 1, &st))
        return ws_cli_fail(&st);
    clip_bench_result r;
    if (clip_bench_run(m, batch, rounds, &r, &st)) {
        clip_model_free(m);
        return ws_cli_fail(&st);
    }
    const wf_arch *a = clip_model_arch(m);
    printf("CLIP image tower: width %d, %d blocks, %d heads, patch %d, %d x %d, output %d (%s)\n",
           a->width, a->layers, a->heads, a->patch, a->resolution, a->resolution, a->output_dim,
           weights ? weights : "random weights");
    printf("batch %d, %d threads, OpenBLAS kernels %s, OpenMP in nn ops %s; best of %d rounds\n\n",
           r.batch, r.threads, r.blas_core, r.nn_parallel ? "on" : "off", r.rounds);
    printf("%-18s %10s %16s %7s\n", "", "time (ms)", "GEMM floor (ms)", "ratio");
    printf("%-18s %10.1f %16.1f %7.2f\n", "forward", 1e3 * r.forward, 1e3 * r.floor_forward,
           r.forward / r.floor_forward);
    printf("%-18s %10.1f %16.1f %7.2f\n", "forward+backward", 1e3 * r.forward_backward,
           1e3 * r.floor_forward_backward, r.forward_backward / r.floor_forward_backward);
    printf("\nactivation arena %.1f MB, peak memory (maxrss) %.1f MB\n", r.arena_bytes / 1e6,
           r.peak_rss_kb / 1e3);
    clip_model_free(m);
    return 0;
}
