/* main.c: dispatches `wiresketch COMMAND ...` to its command. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/outfile.h"
#include "base/runtime.h"
#include "base/version.h"
#include "cli/args.h"
#include "cli/commands.h"

static void usage(FILE *out) {
    fprintf(out, "usage: wiresketch COMMAND [options]   (wiresketch help COMMAND for details; --version)\n\n"
                 "commands:\n");
    for (int i = 0; i < ws_ncommands; i++)
        fprintf(out, "  %-8s %s\n", ws_commands[i].name, ws_commands[i].summary);
    fprintf(out, "\n%s", ws_exit_status_text);
}

/* A closed stdin, stdout or stderr (`>&-`) would hand its number to the
 * next file opened, and printf would then write into an output. Each is
 * held by /dev/null instead: stdout read-only, so that a write still fails
 * (EBADF) and the run ends with exit 1 rather than 0 with nothing written;
 * stderr writable, so that a fit without a visible progress line runs on. */
static void hold_standard_streams(void) {
    static const int mode[3] = {O_RDONLY, O_RDONLY, O_WRONLY};
    for (int fd = 0; fd < 3; fd++)
        if (fcntl(fd, F_GETFD) == -1) {
            int got = open("/dev/null", mode[fd]);
            if (got >= 0 && got != fd) { /* a lower number was closed too: dup into place */
                dup2(got, fd);
                close(got);
            }
        }
}

/* The one place stdout is finished: flushed and closed, every error seen
 * (a write that failed earlier stays flagged). A command that already
 * failed keeps its own line and code. */
static int finish_stdout(int rc) {
    ws_status st;
    ws_status_clear(&st);
    int failed = ws_cli_stdout_check(&st);
    if (fclose(stdout) != 0 && !failed)
        failed = ws_fail(&st, WS_EIO, "standard output: write failed: %s", strerror(errno));
    if (failed && rc == 0) return ws_cli_fail(&st);
    return rc;
}

int main(int argc, char **argv) {
    hold_standard_streams();
    /* Into a file or pipe, what a command prints is written at its end (or
     * at each flush), so that a write that fails fails in the final check,
     * with its reason: after a failed write in mid-output stdio has dropped
     * its buffer and the reason. Help, tables and JSON lines fit in 1 MiB. */
    static char stdout_buffer[1 << 20]; /* glibc sizes a buffer it allocates itself by the file, not by setvbuf */
    if (!isatty(STDOUT_FILENO)) setvbuf(stdout, stdout_buffer, _IOFBF, sizeof stdout_buffer);
    /* OpenMP's waiting, then threads (each command sets its --threads
     * again) and OpenBLAS's kernels before any BLAS call (runtime.h) */
    ws_runtime_reexec_if_needed(argv);
    ws_status st;
    ws_status_clear(&st);
    if (ws_runtime_init(0, &st)) {
        fprintf(stderr, "wiresketch: %s\n", st.msg);
        return ws_exit_code(&st);
    }
    /* A write past `ulimit -f` and one to a reader that went away fail
     * with EFBIG and EPIPE, which every writer checks and names, instead of
     * killing the process with its temporary files left (fit stops on
     * SIGXFSZ like on SIGINT: it installs its own handler). */
    signal(SIGXFSZ, SIG_IGN);
    signal(SIGPIPE, SIG_IGN);
    ws_outfile_remove_on_signals(); /* no temporary file outlives SIGINT, SIGTERM, SIGHUP, SIGXCPU */
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    int rc = -1;
    if (!strcmp(argv[1], "--version")) {
        printf("wiresketch %s (commit %s)\n", ws_version(), ws_build_commit());
        rc = 0;
    }
    /* `help CMD` is `CMD --help` */
    int is_help = !strcmp(argv[1], "help");
    if (rc < 0 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || (is_help && argc == 2))) {
        usage(stdout);
        rc = 0;
    }
    const char *name = argv[is_help ? 2 : 1];
    for (int i = 0; i < ws_ncommands && rc < 0; i++)
        if (!strcmp(name, ws_commands[i].name)) {
            char *help_argv[] = {"--help", NULL};
            rc = is_help ? ws_commands[i].run(1, help_argv) : ws_commands[i].run(argc - 2, argv + 2);
        }
    if (rc < 0) {
        fprintf(stderr, "wiresketch: %s: unknown command (see wiresketch --help)\n", name);
        rc = 2;
    }
    return finish_stdout(rc);
}
