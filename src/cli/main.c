/* main.c: dispatches `wiresketch COMMAND ...` to its command. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/outfile.h"
#include "base/runtime.h"
#include "base/version.h"
#include "cli/commands.h"

static void usage(FILE *out) {
    fprintf(out, "usage: wiresketch COMMAND [options]   (wiresketch help COMMAND for details; --version)\n\n"
                 "commands:\n");
    for (int i = 0; i < ws_ncommands; i++)
        fprintf(out, "  %-8s %s\n", ws_commands[i].name, ws_commands[i].summary);
}

int main(int argc, char **argv) {
    /* OpenMP's waiting, then threads (each command sets its --threads
     * again) and OpenBLAS's kernels before any BLAS call (runtime.h) */
    ws_runtime_reexec_if_needed(argv);
    ws_status st;
    ws_status_clear(&st);
    if (ws_runtime_init(0, &st)) {
        fprintf(stderr, "wiresketch: %s\n", st.msg);
        return ws_exit_code(&st);
    }
    ws_outfile_remove_on_signals(); /* no temporary file outlives SIGINT or SIGTERM */
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("wiresketch %s (commit %s)\n", ws_version(), ws_build_commit());
        return 0;
    }
    /* `help CMD` is `CMD --help` */
    int is_help = !strcmp(argv[1], "help");
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || (is_help && argc == 2)) {
        usage(stdout);
        return 0;
    }
    const char *name = argv[is_help ? 2 : 1];
    for (int i = 0; i < ws_ncommands; i++)
        if (!strcmp(name, ws_commands[i].name)) {
            char *help_argv[] = {"--help", NULL};
            return is_help ? ws_commands[i].run(1, help_argv) : ws_commands[i].run(argc - 2, argv + 2);
        }
    fprintf(stderr, "wiresketch: %s: unknown command (see wiresketch --help)\n", name);
    return 2;
}
