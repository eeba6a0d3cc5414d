/* parallel.h: when the ops of nn/ fork OpenMP teams.
 *
 * OpenBLAS (the pthread build) runs its own worker threads, and OpenMP's
 * idle threads spin for milliseconds after every parallel region (the
 * default OMP_WAIT_POLICY). On a machine with as many threads as cores the
 * two pools then fight: a GEMM that follows an OpenMP region runs at half
 * speed while OpenMP's workers spin, which costs far more than the
 * parallel op saved (measured: forward+backward of ViT-B/32 2.5x slower).
 * So an op forks only when that cannot happen: OpenMP waits passively, or
 * OpenBLAS has no worker threads (ws_runtime_init holds it at one: the
 * GEMMs' own blocks run on OpenMP's team, nn/matmul.c). And only when the
 * work is big enough to pay for waking a team. */
#ifndef NN_PARALLEL_H
#define NN_PARALLEL_H
#include <stddef.h>

/* Read the OpenMP wait policy (once per process: ws_runtime_init calls it;
 * otherwise the first nn_fork does). */
void nn_parallel_init(void);

/* Should an op with `work` elementary steps fork a team? nn/'s ops and the
 * application's per-pixel loops (splat, augmentation, edge maps) all ask. */
int nn_fork(size_t work);

#endif
