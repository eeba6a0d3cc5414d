/* clip_bench.h: how close the image tower runs to its GEMM floor.
 *
 * The floor is the time of the tower's own GEMMs (forward products, and
 * the backward's input-gradient products) through cblas_sgemm alone, on
 * the same buffers and weights: what no implementation of the same
 * products can beat. Rounds alternate the real passes and the floor, so
 * that a busy machine slows both alike; each figure is the best round. */
#ifndef NN_CLIP_BENCH_H
#define NN_CLIP_BENCH_H
#include <stddef.h>
#include "nn/clip.h"

typedef struct {
    int batch, rounds, threads;
    double forward, forward_backward;             /* seconds */
    double floor_forward, floor_forward_backward; /* seconds */
    size_t arena_bytes;                           /* the run's activations */
    long peak_rss_kb;                             /* of the whole process */
    char blas_core[32];                           /* OpenBLAS's kernel set */
    int nn_parallel;                              /* nn ops fork OpenMP teams */
} clip_bench_result;

/* Times `rounds` rounds on a batch of random images with a gradient seed
 * on the embedding and on blocks 2 and 3 (the default loss's features). */
int clip_bench_run(const clip_model *m, int batch, int rounds, clip_bench_result *res,
                   ws_status *st);

#endif
