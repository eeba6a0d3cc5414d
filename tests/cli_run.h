/* cli_run.h: running the command-line program from a test.
 *
 * run_cmd(out, size, fmt, ...) runs a shell command line (stdout and stderr
 * together), stores what it printed (up to size - 1 bytes) in `out` and
 * returns its exit code, -1 when it could not run or did not exit.
 * read_text(path, buf, size) reads a file's text for a test to search.
 * temporaries_in(dir, name) counts the program's temporary files there. */
#ifndef WS_CLI_RUN_H
#define WS_CLI_RUN_H
#include <dirent.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

static int run_cmd(char *out, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4), unused));
static int run_cmd(char *out, size_t size, const char *fmt, ...) {
    char cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd - 8, fmt, ap);
    va_end(ap);
    strcat(cmd, " 2>&1");
    FILE *p = popen(cmd, "r");
    out[0] = '\0';
    if (!p) return -1;
    size_t n = 0, got;
    while (n + 1 < size && (got = fread(out + n, 1, size - 1 - n, p)) > 0) n += got;
    out[n] = '\0';
    char sink[4096]; /* the rest, so that the command is not killed by SIGPIPE */
    while (fread(sink, 1, sizeof sink, p) > 0) {
    }
    int status = pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* The first size - 1 bytes of a file as a string ("" when unreadable). */
static inline const char *read_text(const char *path, char *buf, size_t size) {
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(buf, 1, size - 1, f) : 0;
    if (f) fclose(f);
    buf[n] = '\0';
    return buf;
}

/* The program's temporary files in folder dir (base/outfile.h:
 * .wiresketch.tmp.PID.N.NAME), of target NAME `name` or, for NULL, any. */
static inline int temporaries_in(const char *dir, const char *name) {
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));) {
        const char *c = e->d_name;
        if (strncmp(c, ".wiresketch.tmp.", 16)) continue;
        c += 16;
        for (int field = 0; field < 2 && c; field++) c = strchr(c, '.') ? strchr(c, '.') + 1 : NULL;
        n += c && (!name || !strcmp(c, name));
    }
    if (d) closedir(d);
    return n;
}

/* A shell command line's exit: 1 when it ran and exited 0. */
static inline int sh(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static inline int sh(const char *fmt, ...) {
    char cmd[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    return system(cmd) == 0;
}

#endif
