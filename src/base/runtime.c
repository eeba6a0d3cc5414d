/* runtime.c: threads, OpenBLAS kernels and OpenMP's waiting (runtime.h). */
#include <cblas.h>
#include <omp.h>
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include "base/runtime.h"
#include "nn/parallel.h"

/* OpenBLAS's DYNAMIC_ARCH entry points (exported by Debian's 0.3.21, in no
 * header): weak, so that another BLAS links too and is left alone. */
extern void gotoblas_dynamic_init(void) __attribute__((weak));
extern void gotoblas_dynamic_quit(void) __attribute__((weak));

static ws_blas_kernels kernels;
static int kernels_chosen;

/* OpenBLAS's x86-64 kernel names by the instructions they use: 4 AVX-512,
 * 3 AVX2+FMA, 2 AVX, 1 SSE4-era, 0 older; -1: a name not ranked here. */
static int rank(const char *core) {
    static const struct {
        const char *name;
        int rank;
    } known[] = {{"SapphireRapids", 4}, {"Cooperlake", 4}, {"SkylakeX", 4},  {"Haswell", 3},
                 {"Zen", 3},            {"Sandybridge", 2}, {"Bulldozer", 2}, {"Piledriver", 2},
                 {"Steamroller", 2},    {"Excavator", 2},  {"Nehalem", 1},   {"Penryn", 1},
                 {"Core2", 1},          {"Dunnington", 1}, {"Barcelona", 1}, {"Prescott", 0},
                 {"Atom", 0},           {"Nano", 0},       {"Bobcat", 0},    {"Opteron_SSE3", 0},
                 {"Opteron", 0},        {"Athlon", 0},     {"Banias", 0},    {"Northwood", 0},
                 {"Coppermine", 0},     {"Katmai", 0}};
    for (size_t i = 0; core && i < sizeof known / sizeof known[0]; i++)
        if (!strcasecmp(core, known[i].name)) return known[i].rank;
    return -1;
}

/* The strongest kernels the CPU's features allow, by rank (NULL: none). */
static const char *best_for_cpu(const char **features) {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl")) {
        *features = "AVX512F+BW+DQ+VL";
        return "SkylakeX";
    }
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        *features = "AVX2+FMA";
        return "Haswell";
    }
    if (__builtin_cpu_supports("avx")) {
        *features = "AVX";
        return "Sandybridge";
    }
    if (__builtin_cpu_supports("sse4.2")) {
        *features = "SSE4.2";
        return "Nehalem";
    }
    *features = "no SSE4.2";
    return NULL;
}

static void choose_kernels(void) {
    ws_blas_kernels *k = &kernels;
    const char *core = openblas_get_corename();
    snprintf(k->before, sizeof k->before, "%s", core ? core : "");
    memcpy(k->after, k->before, sizeof k->after);
    const char *user = getenv("OPENBLAS_CORETYPE"), *features, *best = best_for_cpu(&features);
    if (user) {
        snprintf(k->why, sizeof k->why, "OPENBLAS_CORETYPE=%s set in the environment: kept (the CPU's %s allow %s)",
                 user, features, best ? best : "no better");
    } else if (!gotoblas_dynamic_init || !gotoblas_dynamic_quit) {
        snprintf(k->why, sizeof k->why, "not an OpenBLAS built with DYNAMIC_ARCH: kept");
    } else if (!best || rank(core) < 0 || rank(core) >= rank(best)) {
        snprintf(k->why, sizeof k->why, "OpenBLAS's choice; the CPU's features (%s) allow no stronger kernels",
                 features);
    } else {
        setenv("OPENBLAS_CORETYPE", best, 1);
        gotoblas_dynamic_quit();
        gotoblas_dynamic_init();
        unsetenv("OPENBLAS_CORETYPE");
        core = openblas_get_corename();
        snprintf(k->after, sizeof k->after, "%s", core ? core : "");
        snprintf(k->why, sizeof k->why, "OpenBLAS chose %.31s by CPU model; the CPU has %s: %s", k->before,
                 features, best);
    }
}

int ws_runtime_check_threads(int threads, ws_status *st) {
    if (threads < 0 || threads > WS_MAX_THREADS)
        return ws_fail(st, WS_EUSAGE, "--threads: %d is not in [0, %d] (0: one per core)", threads,
                       WS_MAX_THREADS);
    return WS_OK;
}

/* OMP_STACKSIZE as libgomp reads it (a number, then B, K, M or G; K when
 * none), checked before the first parallel region: outside the bounds
 * libgomp's first thread creation fails ("Thread creation failed") and
 * ends the process with its own line, whatever the run was doing. */
/* 64 KiB fails thread creation here (glibc's minimum plus the libraries'
 * thread-local storage); 72 KiB ran eval and render: 128 KiB leaves room
 * for deeper frames */
#define MIN_STACK ((unsigned long long)128 << 10)
#define MAX_STACK ((unsigned long long)256 << 20) /* each of up to WS_MAX_THREADS threads maps one */
static int check_stack_size(ws_status *st) {
    const char *text = getenv("OMP_STACKSIZE");
    if (!text) return WS_OK;
    char *end;
    errno = 0;
    unsigned long long n = strtoull(text, &end, 10);
    while (*end == ' ' || *end == '\t') end++;
    unsigned shift = 10;
    if (*end) {
        const char *units = "BKMG", *u = strchr(units, toupper((unsigned char)*end));
        shift = u ? 10 * (unsigned)(u - units) : 99;
        end++;
    }
    while (*end == ' ' || *end == '\t') end++;
    int parsed = end != text && !*end && shift < 99 && errno == 0 && isdigit((unsigned char)text[strspn(text, " \t")]);
    if (!parsed || n > MAX_STACK >> shift || n << shift < MIN_STACK)
        return ws_fail(st, WS_EUSAGE,
                       "OMP_STACKSIZE=%s: %s; each thread needs from 128K to 256M (unset it: the default "
                       "is enough)", text, parsed ? "out of range" : "not a size such as 4M");
    return WS_OK;
}

int ws_runtime_init(int threads, ws_status *st) {
    if (ws_runtime_check_threads(threads, st)) return st->code;
    if (!kernels_chosen && check_stack_size(st)) return st->code;
    if (!kernels_chosen) {
        choose_kernels();
        nn_parallel_init();
        kernels_chosen = 1;
    }
    int n = threads ? threads : omp_get_num_procs();
    if (n > WS_MAX_THREADS) n = WS_MAX_THREADS;
    omp_set_num_threads(n);
    openblas_set_num_threads(1); /* nn/ threads its GEMMs itself (nn/matmul.c) */
    return WS_OK;
}

int ws_runtime_threads(void) { return omp_get_max_threads(); }

const ws_blas_kernels *ws_runtime_kernels(void) { return &kernels; }

void ws_runtime_reexec_if_needed(char **argv) {
    if (getenv("OMP_WAIT_POLICY")) return;
    setenv("OMP_WAIT_POLICY", "passive", 1);
    execv("/proc/self/exe", argv);
}
