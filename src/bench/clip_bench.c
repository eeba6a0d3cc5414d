/* clip_bench.c: timing of the image tower against its GEMM floor (clip_bench.h). */
#include <cblas.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <time.h>
#include "bench/clip_bench.h"
#include "nn/matmul.h"
#include "nn/parallel.h"
#include "nn/base/rng.h"

enum { SEEDED_BLOCKS = 2 }; /* blocks 2 and 3, when the model has them */

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static float *random_floats(size_t n, ws_rng *rng, double lo, double hi, ws_status *st) {
    float *x = ws_malloc(n * sizeof *x, "benchmark inputs", st);
    if (x)
        for (size_t i = 0; i < n; i++) x[i] = (float)(lo + (hi - lo) * ws_rng_uniform(rng));
    return x;
}

/* The run's GEMMs of one pass: as nn/ runs them (nn_gemm_run's blocks), or
 * whole, one cblas_sgemm call each. */
static void floor_pass(clip_run *r, int backward, int whole) {
    const nn_tape *t = clip_run_tape(r);
    for (int k = 0; k < t->nops; k++) {
        const nn_op *op = &t->ops[backward ? t->nops - 1 - k : k];
        nn_gemm g;
        if (!nn_op_gemm(op, backward, &g)) continue;
        if (whole)
            nn_gemm_columns(&g, 0.0f, 0, g.n);
        else
            nn_gemm_run(&g, 0.0f);
    }
}

void ws_clip_gemm_floor(clip_run *r, int backward) { floor_pass(r, backward, 0); }

/* Both passes' GEMMs whole, on OpenBLAS's own threads (as many as OpenMP
 * has): what the blocks cost against OpenBLAS's threading. Seconds. */
static double floor_openblas(clip_run *r) {
    int was = openblas_get_num_threads();
    openblas_set_num_threads(omp_get_max_threads());
    double t0 = now();
    floor_pass(r, 0, 1);
    floor_pass(r, 1, 1);
    double t = now() - t0;
    openblas_set_num_threads(was);
    return t;
}

int ws_clip_bench_run(const clip_model *m, int batch, int rounds, ws_clip_bench_result *res,
                      ws_status *st) {
    const wf_arch *a = clip_model_arch(m);
    if (rounds < 1) return ws_fail(st, WS_EUSAGE, "clip bench: rounds %d must be at least 1", rounds);
    clip_run *run;
    clip_run_options opt = {batch, a->layers - 1, 1, 1, 0};
    if (clip_run_create(&run, m, &opt, st)) return st->code;
    int tokens = 1 + (a->resolution / a->patch) * (a->resolution / a->patch);
    size_t pixels = (size_t)batch * 3 * a->resolution * a->resolution;
    size_t hidden = (size_t)batch * tokens * a->width;
    ws_rng rng;
    ws_rng_seed(&rng, 1);
    const float **d_hidden = ws_calloc((size_t)a->layers, sizeof *d_hidden, "benchmark seeds", st);
    float *images = random_floats(pixels, &rng, 0, 1, st);
    float *d_images = ws_malloc(pixels * sizeof *d_images, "benchmark gradients", st);
    float *d_embedding = random_floats((size_t)batch * a->output_dim, &rng, -1, 1, st);
    float *d_blocks = random_floats(SEEDED_BLOCKS * hidden, &rng, -1e-3, 1e-3, st);
    nn_tape *tape = clip_run_tape(run);
    size_t nslots = 2 * (size_t)tape->nops;
    double *op_seconds = ws_malloc(nslots * sizeof *op_seconds, "benchmark profile", st);
    double *op_best = ws_malloc(nslots * sizeof *op_best, "benchmark profile", st);
    int rc = WS_OK;
    if (!d_hidden || !images || !d_images || !d_embedding || !d_blocks || !op_seconds || !op_best) {
        rc = st->code;
        goto done;
    }
    for (int k = 0; k < SEEDED_BLOCKS && 2 + k < a->layers; k++) d_hidden[2 + k] = d_blocks + k * hidden;

    *res = (ws_clip_bench_result){.batch = batch, .rounds = rounds, .threads = omp_get_max_threads()};
    res->forward = res->forward_backward = res->floor_forward = res->floor_forward_backward = INFINITY;
    for (size_t i = 0; i < nslots; i++) op_best[i] = INFINITY;
    nn_tape_profile(tape, op_seconds);
    /* one unmeasured round: page faults of the arena, OpenBLAS's threads */
    for (int r = -1; r < rounds; r++) {
        double t0 = now();
        if (clip_forward(run, images, st)) {
            rc = st->code;
            goto done;
        }
        double t1 = now();
        if (clip_backward(run, d_hidden, NULL, d_embedding, d_images, st)) {
            rc = st->code;
            goto done;
        }
        double t2 = now();
        ws_clip_gemm_floor(run, 0);
        double t3 = now();
        ws_clip_gemm_floor(run, 1);
        double t4 = now();
        if (r < 0) continue;
        res->forward = fmin(res->forward, t1 - t0);
        res->forward_backward = fmin(res->forward_backward, t2 - t0);
        res->floor_forward = fmin(res->floor_forward, t3 - t2);
        res->floor_forward_backward = fmin(res->floor_forward_backward, t4 - t2);
        for (size_t i = 0; i < nslots; i++) op_best[i] = fmin(op_best[i], op_seconds[i]);
    }
    nn_tape_profile(tape, NULL);
    /* after the rounds: OpenBLAS's threads spin for a while after each
     * call, which would slow the rounds' own passes */
    res->floor_openblas = INFINITY;
    for (int r = -1; r < rounds; r++) {
        double t = floor_openblas(run);
        if (r >= 0) res->floor_openblas = fmin(res->floor_openblas, t);
    }
    for (int i = 0; i < tape->nops; i++) {
        res->op_forward[tape->ops[i].kind] += tape->ops[i].forward ? op_best[i] : 0.0;
        res->op_backward[tape->ops[i].kind] += op_best[tape->nops + i];
    }
    res->arena_bytes = clip_run_bytes(run);
    res->nn_parallel = nn_fork((size_t)-1);
done:
    clip_run_free(run);
    free(d_hidden);
    free(images);
    free(d_images);
    free(d_embedding);
    free(d_blocks);
    free(op_seconds);
    free(op_best);
    return rc;
}
