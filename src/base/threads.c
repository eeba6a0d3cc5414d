/* threads.c: the thread count of OpenMP and OpenBLAS (see threads.h). */
#include <cblas.h>
#include <omp.h>
#include "base/threads.h"

void ws_threads_set(int n) {
    if (n <= 0) n = omp_get_num_procs();
    omp_set_num_threads(n);
    openblas_set_num_threads(n);
}

int ws_threads_get(void) { return omp_get_max_threads(); }
