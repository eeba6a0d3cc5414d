/* parallel.c: the forking rule of nn/ (parallel.h). */
#include <cblas.h>
#include <omp.h>
#include <stdlib.h>
#include <strings.h>
#include "parallel.h"

/* Below this many steps a team costs more to wake than it saves. */
#define MIN_WORK 32768

/* The wait policy libgomp was started with: it reads OMP_WAIT_POLICY once,
 * when it loads, so one reading serves the whole process. -1: not read. */
static int passive_wait = -1;

void nn_parallel_init(void) {
    const char *policy = getenv("OMP_WAIT_POLICY");
    passive_wait = policy && !strcasecmp(policy, "passive");
}

int nn_fork(size_t work) {
    if (work < MIN_WORK || omp_get_max_threads() < 2) return 0;
    if (passive_wait < 0) nn_parallel_init();
    return passive_wait || openblas_get_num_threads() < 2;
}
