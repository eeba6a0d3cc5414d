/* clip_bench.h: how close the image tower runs to its GEMM floor.
 *
 * The floor is the time of the tower's own GEMMs (forward products, and
 * the backward's input-gradient products) through cblas_sgemm alone, on
 * the same buffers and weights: what no implementation of the same
 * products can beat. Rounds alternate the real passes and the floor, so
 * that a busy machine slows both alike; each figure is the best round.
 * The rounds also time every op of the tape (nn_tape_profile), to show
 * where the time above the floor goes. The floor runs the GEMMs as nn/
 * does, in fixed blocks of columns on OpenMP's threads; the same GEMMs run
 * whole on OpenBLAS's own threads are timed too (floor_openblas). */
#ifndef WS_CLIP_BENCH_H
#define WS_CLIP_BENCH_H
#include <stddef.h>
#include "nn/clip.h"

typedef struct {
    int batch, rounds, threads;
    double forward, forward_backward;             /* seconds */
    double floor_forward, floor_forward_backward; /* seconds */
    /* the floor's GEMMs whole, one cblas_sgemm call each on OpenBLAS's own
     * threads (timed after the rounds): what nn/'s fixed blocks cost, whose
     * bits do not depend on the thread count */
    double floor_openblas;
    size_t arena_bytes;                           /* the run's activations */
    int nn_parallel;                              /* nn ops fork OpenMP teams */
    /* seconds per kind of op (nn_op_kind), each op's best round, summed */
    double op_forward[NN_OP_KINDS], op_backward[NN_OP_KINDS];
} ws_clip_bench_result;

/* Times `rounds` rounds on a batch of random images with a gradient seed
 * on the embedding and on blocks 2 and 3 (the default loss's features). */
int ws_clip_bench_run(const clip_model *m, int batch, int rounds, ws_clip_bench_result *res,
                      ws_status *st);

/* Runs only the run's GEMMs (nn_op_gemm) through cblas_sgemm, on its own
 * buffers and weights: the forward products without their biases, or the
 * backward's input-gradient products (a run made with need_grad). The
 * time no implementation of the same products can beat. Clobbers the
 * run's activations. */
void ws_clip_gemm_floor(clip_run *r, int backward);

#endif
