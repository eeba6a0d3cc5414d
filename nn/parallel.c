/* parallel.c: the forking rule of nn/ (parallel.h). */
#include <cblas.h>
#include <omp.h>
#include <stdlib.h>
#include <strings.h>
#include "parallel.h"

/* Below this many steps a team costs more to wake than it saves. */
#define MIN_WORK 32768

int nn_fork(size_t work) {
    if (work < MIN_WORK || omp_get_max_threads() < 2) return 0;
    const char *policy = getenv("OMP_WAIT_POLICY");
    int passive = policy && !strcasecmp(policy, "passive");
    return passive || openblas_get_num_threads() < 2;
}
