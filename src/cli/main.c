/* main.c: dispatches `wiresketch COMMAND ...` to its command. */
#include <cblas.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include "base/outfile.h"
#include "cli/commands.h"

static void usage(FILE *out) {
    fprintf(out, "usage: wiresketch COMMAND [options]   (wiresketch COMMAND --help for details)\n\n"
                 "commands:\n");
    for (int i = 0; i < ws_ncommands; i++)
        fprintf(out, "  %-8s %s\n", ws_commands[i].name, ws_commands[i].summary);
}

/* Two settings that OpenBLAS and OpenMP read only when they load, so the
 * program sets them and runs itself again, once:
 * - OpenBLAS 0.3.21 does not recognise some recent CPUs and falls back to
 *   its SSE3 "Prescott" kernels, about 4x slower on CLIP's GEMMs: name the
 *   kernels the CPU can run (OPENBLAS_CORETYPE);
 * - OpenMP's idle threads spin after each parallel region and slow the GEMMs
 *   that follow: let them sleep (OMP_WAIT_POLICY=passive).
 * A user's own setting of either is left alone, and so is everything when
 * the re-run fails (the program then goes on as it is). */
static void tune_runtime(char **argv) {
    int changed = 0;
    if (!getenv("OMP_WAIT_POLICY")) {
        setenv("OMP_WAIT_POLICY", "passive", 1);
        changed = 1;
    }
    const char *core = openblas_get_corename();
    if (!getenv("OPENBLAS_CORETYPE") && core && !strcasecmp(core, "Prescott")) {
        __builtin_cpu_init();
        const char *better = __builtin_cpu_supports("avx512f") ? "SkylakeX"
                             : __builtin_cpu_supports("avx2")  ? "Haswell"
                                                               : NULL;
        if (better) {
            setenv("OPENBLAS_CORETYPE", better, 1);
            changed = 1;
        }
    }
    if (changed) execv("/proc/self/exe", argv);
}

int main(int argc, char **argv) {
    tune_runtime(argv);
    ws_outfile_remove_on_signals(); /* no temporary file outlives SIGINT or SIGTERM */
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return 0;
    }
    for (int i = 0; i < ws_ncommands; i++)
        if (!strcmp(argv[1], ws_commands[i].name)) return ws_commands[i].run(argc - 2, argv + 2);
    fprintf(stderr, "wiresketch: %s: unknown command (see wiresketch --help)\n", argv[1]);
    return 2;
}
