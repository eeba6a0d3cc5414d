/* test_runtime.c: the run-time set-up (base/runtime.h): the thread bound
 * and its message, and the OpenBLAS kernel switch: a child started with
 * OPENBLAS_CORETYPE=Prescott (the SSE3 kernels OpenBLAS falls back to on
 * models it does not know) removes the variable before ws_runtime_init, as
 * if OpenBLAS had chosen Prescott itself, and must then run the strongest
 * kernels its CPU's features allow, with GEMMs that still compute right. */
#include <cblas.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include "base/runtime.h"
#include "check.h"

/* Largest |C - A B| of a 64 x 48 x 80 sgemm against a double-precision sum. */
static double gemm_error(void) {
    enum { M = 64, K = 48, N = 80 };
    static float a[M * K], b[K * N], c[M * N];
    for (int i = 0; i < M * K; i++) a[i] = (float)((i * 37 % 101) / 101.0 - 0.5);
    for (int i = 0; i < K * N; i++) b[i] = (float)((i * 53 % 89) / 89.0 - 0.5);
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, M, N, K, 1.0f, a, K, b, N, 0.0f, c, N);
    double worst = 0;
    for (int i = 0; i < M; i++)
        for (int j = 0; j < N; j++) {
            double s = 0;
            for (int k = 0; k < K; k++) s += (double)a[i * K + k] * b[k * N + j];
            worst = fmax(worst, fabs(s - c[i * N + j]));
        }
    return worst;
}

static int child(void) {
    unsetenv("OPENBLAS_CORETYPE");
    ws_status st = {0};
    CHECK(ws_runtime_init(1, &st) == WS_OK, "runtime: %s", st.msg);
    const ws_blas_kernels *k = ws_runtime_kernels();
    __builtin_cpu_init();
    const char *best = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                               __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl")
                           ? "SkylakeX"
                       : __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? "Haswell"
                       : __builtin_cpu_supports("avx")                                    ? "Sandybridge"
                       : __builtin_cpu_supports("sse4.2")                                 ? "Nehalem"
                                                                                          : "Prescott";
    CHECK(!strcmp(k->before, "Prescott"), "OpenBLAS chose %s, not the Prescott it was told", k->before);
    CHECK(!strcmp(k->after, best) && !strcmp(openblas_get_corename(), best),
          "kernels %s (%s), the CPU allows %s: %s", k->after, openblas_get_corename(), best, k->why);
    CHECK(!getenv("OPENBLAS_CORETYPE"), "the environment keeps OPENBLAS_CORETYPE");
    CHECK(gemm_error() < 1e-5, "sgemm with the new kernels is off by %g", gemm_error());
    printf("kernels: %s -> %s (%s)\n", k->before, k->after, k->why);
    return check_failed ? 1 : 0; /* the parent counts this run as one check */
}

int main(int argc, char **argv) {
    if (getenv("WS_TEST_RUNTIME_CHILD")) return child();
    ws_status st = {0};
    CHECK(ws_runtime_init(-1, &st) == WS_EUSAGE &&
              !strcmp(st.msg, "--threads: -1 is not in [0, 1024] (0: one per core)"),
          "negative threads: %s", st.msg);
    ws_status_clear(&st);
    CHECK(ws_runtime_init(WS_MAX_THREADS + 1, &st) == WS_EUSAGE &&
              !strcmp(st.msg, "--threads: 1025 is not in [0, 1024] (0: one per core)"),
          "too many threads: %s", st.msg);
    ws_status_clear(&st);
    CHECK(ws_runtime_init(2, &st) == WS_OK && ws_runtime_threads() == 2, "2 threads: %d", ws_runtime_threads());
    CHECK(ws_runtime_init(1, &st) == WS_OK && ws_runtime_threads() == 1, "1 thread: %d", ws_runtime_threads());
    const char *user = getenv("OPENBLAS_CORETYPE");
    CHECK(!user || (!strcmp(ws_runtime_kernels()->after, ws_runtime_kernels()->before) &&
                    strstr(ws_runtime_kernels()->why, "set in the environment: kept")),
          "a user's OPENBLAS_CORETYPE=%s was not kept: %s", user, ws_runtime_kernels()->why);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "WS_TEST_RUNTIME_CHILD=1 OPENBLAS_CORETYPE=Prescott %s", argv[0]);
    int rc = system(cmd);
    CHECK(WIFEXITED(rc) && WEXITSTATUS(rc) == 0, "the child with Prescott kernels failed (%d)", rc);
    return check_summary();
}
