/* runtime.h: the one set-up call of the library's run time: how many
 * threads, and which OpenBLAS kernels. The `wiresketch` program and a
 * program embedding the library (tools/embed_example.c) both call
 * ws_runtime_init before anything else.
 *
 * Threads: the count is OpenMP's; OpenBLAS is held at one thread, and
 * nn/ shares out each GEMM's column blocks over the OpenMP team
 * (nn/matmul.c), so that a run gives the same bits on any thread count
 * whatever kernels OpenBLAS runs (its own threading rounds differently
 * from its single-threaded calls with some of them, Haswell's).
 *
 * Kernels: OpenBLAS 0.3.21 picks its kernels from the CPU's vendor and
 * model when it loads, and takes weaker ones than the CPU can run on
 * models it does not know (AMD Zen 4/5 get "Zen", AVX2, about 1.7x slower
 * GEMMs; some Intel models "Prescott", SSE3, about 4x slower). The first
 * ws_runtime_init reads the CPU's features instead (cpuid: AVX512F, BW, DQ
 * and VL -> SkylakeX; AVX2 and FMA -> Haswell; AVX -> Sandybridge; SSE4.2
 * -> Nehalem) and, where OpenBLAS's choice ranks lower, switches to those
 * kernels in this process (OpenBLAS's own gotoblas_dynamic_quit/init, as
 * its constructor runs them, with OPENBLAS_CORETYPE set for the moment and
 * then restored). An OPENBLAS_CORETYPE in the environment is the user's
 * choice and is kept; so is everything when the BLAS is not an OpenBLAS
 * built with DYNAMIC_ARCH (Debian's is). It must run before any BLAS call
 * of the process; an embedding program gets exactly what `wiresketch` gets.
 *
 * OpenMP's waiting is the one setting a library cannot change in-process:
 * libgomp reads OMP_WAIT_POLICY once, when it loads, and its idle threads
 * otherwise spin after each parallel region and slow the GEMMs that follow.
 * ws_runtime_reexec_if_needed sets OMP_WAIT_POLICY=passive and re-executes
 * the program (`wiresketch` does so first thing; an embedding program may
 * call it too, or set the variable in its environment): spinning threads
 * take cores from the other processes of a shared machine, and from
 * OpenBLAS's threads where a program gives it some (nn/parallel.h). */
#ifndef WS_RUNTIME_H
#define WS_RUNTIME_H
#include "nn/base/status.h"

/* At most this many threads (--threads, and 0 = one per core). */
#define WS_MAX_THREADS 1024

/* threads in [0, WS_MAX_THREADS], 0 = one per core (at most
 * WS_MAX_THREADS); WS_EUSAGE otherwise. May be called again to change the
 * thread count; the kernels are chosen once. */
int ws_runtime_init(int threads, ws_status *st);
/* The thread-count check alone (options checked before anything runs). */
int ws_runtime_check_threads(int threads, ws_status *st);

/* The thread count in force. */
int ws_runtime_threads(void);

/* The kernel choice of the first ws_runtime_init. */
typedef struct {
    char before[32]; /* OpenBLAS's own choice ("" before ws_runtime_init) */
    char after[32];  /* the kernels in use */
    char why[160];   /* why they changed or stayed */
} ws_blas_kernels;
const ws_blas_kernels *ws_runtime_kernels(void);

/* Unless OMP_WAIT_POLICY is set: sets it to passive and runs argv again
 * (/proc/self/exe); returns only when it is set or the re-run fails. Call
 * first thing in main, before any OpenMP region. */
void ws_runtime_reexec_if_needed(char **argv);

#endif
