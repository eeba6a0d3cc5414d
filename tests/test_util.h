/* test_util.h: a test's temporary folder, its files and its runs of the
 * program (or of a shell line).
 *
 * Folders and files:
 *   test_tmpdir(name)        a new empty folder /tmp/ws_test_NAME_XXXXXX,
 *                            removed with all it holds when the program
 *                            exits (unless the test removed it), kept (and
 *                            named on stderr) when a check failed; when
 *                            none can be made the program ends.
 *   remove_tree(path)        removes a file or a folder and all it holds.
 *   slurp(path, &size)       a whole file, malloc'd and NUL-terminated
 *                            (NULL when unreadable; size may be NULL).
 *   same_file(a, b)          1 when both files read and hold the same bytes.
 *   read_text(path, buf, n)  the first n - 1 bytes of a file, as a string.
 *   file_has(path, text)     1 when the file reads and holds text.
 *   temporaries_in(dir, nm)  the program's temporary files in dir.
 * Runs:
 *   program_path()           $BUILD/wiresketch (build/wiresketch).
 *   run(fmt, ...)            `wiresketch ARGS` through the shell, stdout and
 *                            stderr into the first test_tmpdir's stdout.txt
 *                            and stderr.txt (read them with run_stdout() and
 *                            run_stderr()); its exit code.
 *   run_limited(bytes, ...)  run() with no file it writes over `bytes`.
 *   run_cmd(out, n, fmt, ..) a shell line, what it printed (stdout and
 *                            stderr) in out; its exit code.
 *   sh(fmt, ...)             a shell line for a set-up: 1 when it exited 0.
 * Exit codes are -1 when the command could not run or did not exit. */
#ifndef WS_TEST_UTIL_H
#define WS_TEST_UTIL_H
#include <dirent.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include "check.h"

/* ------------------------------------------------------------ folders */

/* Removes path: a file, a link (not what it points to) or a folder and
 * everything below it. 0 on success. */
static inline int remove_tree(const char *path) {
    struct stat s;
    if (lstat(path, &s)) return -1;
    if (!S_ISDIR(s.st_mode)) return unlink(path);
    DIR *d = opendir(path);
    int rc = d ? 0 : -1;
    for (struct dirent *e; d && (e = readdir(d));) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        char child[4096];
        int n = snprintf(child, sizeof child, "%s/%s", path, e->d_name);
        rc |= n < 0 || (size_t)n >= sizeof child ? -1 : remove_tree(child);
    }
    if (d) closedir(d);
    return rc | rmdir(path);
}

/* The folders test_tmpdir made, and the process that made them (a forked
 * child that exits must not remove its parent's folders). */
#define TEST_TMPDIRS 8
static char test_tmpdirs[TEST_TMPDIRS][256];
static int test_tmpdir_count;
static pid_t test_tmpdir_owner;

static void test_tmpdir_remove(void) {
    if (getpid() != test_tmpdir_owner) return;
    for (int k = 0; k < test_tmpdir_count; k++)
        if (check_failed)
            fprintf(stderr, "kept %s (a check failed)\n", test_tmpdirs[k]);
        else if (access(test_tmpdirs[k], F_OK) == 0 && remove_tree(test_tmpdirs[k]))
            fprintf(stderr, "could not remove %s\n", test_tmpdirs[k]);
}

/* A new empty folder /tmp/ws_test_NAME_XXXXXX, removed at exit unless a
 * check failed. When none can be made, that is one failed check and the
 * program ends with its summary. */
static inline const char *test_tmpdir(const char *name) {
    char *dir = test_tmpdir_count < TEST_TMPDIRS ? test_tmpdirs[test_tmpdir_count] : NULL;
    if (dir) snprintf(dir, sizeof test_tmpdirs[0], "/tmp/ws_test_%s_XXXXXX", name);
    if (!dir || !mkdtemp(dir)) {
        CHECK(0, "test_tmpdir %s: %s", name, dir ? "mkdtemp failed" : "too many folders");
        exit(check_summary());
    }
    if (test_tmpdir_count++ == 0) {
        test_tmpdir_owner = getpid();
        atexit(test_tmpdir_remove);
    }
    return dir;
}

/* -------------------------------------------------------------- files */

/* The whole file, malloc'd with a NUL after it (the caller frees it); its
 * size in *size when size is not NULL. NULL when it cannot be read. */
static inline char *slurp(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    char *data = NULL;
    long n = -1;
    if (f && fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (data = malloc((size_t)n + 1)) && fread(data, 1, (size_t)n, f) != (size_t)n) {
        free(data);
        data = NULL;
    }
    if (f) fclose(f);
    if (data) data[n] = '\0';
    if (size) *size = data ? (size_t)n : 0;
    return data;
}

/* 1 when both files can be read and hold the same bytes. */
static inline int same_file(const char *a, const char *b) {
    size_t na, nb;
    char *x = slurp(a, &na), *y = slurp(b, &nb);
    int same = x && y && na == nb && !memcmp(x, y, na);
    free(x);
    free(y);
    return same;
}

/* The first size - 1 bytes of a file as a string ("" when unreadable). */
static inline const char *read_text(const char *path, char *buf, size_t size) {
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(buf, 1, size - 1, f) : 0;
    if (f) fclose(f);
    buf[n] = '\0';
    return buf;
}

/* 1 when the file can be read and holds `text`. */
static inline int file_has(const char *path, const char *text) {
    char *data = slurp(path, NULL);
    int has = data && strstr(data, text);
    free(data);
    return has;
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

/* --------------------------------------------------------------- runs */

/* The program under test: $BUILD/wiresketch, build/wiresketch without BUILD. */
static inline const char *program_path(void) {
    static char path[300];
    const char *build = getenv("BUILD");
    snprintf(path, sizeof path, "%s/wiresketch", build && *build ? build : "build");
    return path;
}

/* Runs `wiresketch ARGS` (ARGS from fmt) through the shell with stdout and
 * stderr in the first test_tmpdir's stdout.txt and stderr.txt; with
 * fsize_limit > 0 no file it writes may grow beyond that many bytes
 * (RLIMIT_FSIZE: a write past it fails with EFBIG, as on a full disk, and
 * SIGXFSZ is ignored so that the write reports it). A run that hangs (a
 * FIFO opened for reading) is ended after 600 s. Returns the exit code. */
static inline int run_program(long fsize_limit, const char *fmt, va_list ap) {
    char args[6000], cmd[8192];
    vsnprintf(args, sizeof args, fmt, ap);
    const char *dir = test_tmpdir_count ? test_tmpdirs[0] : ".";
    snprintf(cmd, sizeof cmd, "%s %s >%s/stdout.txt 2>%s/stderr.txt", program_path(), args, dir, dir);
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        alarm(600);
        if (fsize_limit > 0) {
            struct rlimit rl = {(rlim_t)fsize_limit, (rlim_t)fsize_limit};
            signal(SIGXFSZ, SIG_IGN);
            if (setrlimit(RLIMIT_FSIZE, &rl) != 0) _exit(126);
        }
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    int status;
    if (pid < 0 || waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static int run(const char *fmt, ...) __attribute__((format(printf, 1, 2), unused));
static int run(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    int rc = run_program(0, fmt, ap);
    va_end(ap);
    return rc;
}

static int run_limited(long fsize_limit, const char *fmt, ...) __attribute__((format(printf, 2, 3), unused));
static int run_limited(long fsize_limit, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    int rc = run_program(fsize_limit, fmt, ap);
    va_end(ap);
    return rc;
}

/* What the last run() printed on stdout / stderr (up to 1 MiB each). */
static inline const char *run_output(const char *name) {
    static char text[2][1 << 20];
    char path[300];
    int k = !strcmp(name, "stderr.txt");
    snprintf(path, sizeof path, "%s/%s", test_tmpdir_count ? test_tmpdirs[0] : ".", name);
    return read_text(path, text[k], sizeof text[k]);
}
#define run_stdout() run_output("stdout.txt")
#define run_stderr() run_output("stderr.txt")

/* Runs a shell command line, stores what it printed on stdout and stderr
 * (up to size - 1 bytes; the line's own redirections apply first: "CMD
 * 2>/dev/null" gives its stdout alone) in `out` and returns its exit code. */
static int run_cmd(char *out, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4), unused));
static int run_cmd(char *out, size_t size, const char *fmt, ...) {
    char line[8192], cmd[8208];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    snprintf(cmd, sizeof cmd, "( %s\n) 2>&1", line);
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

/* A shell command line's exit: 1 when it ran and exited 0. */
static inline int sh(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static inline int sh(const char *fmt, ...) {
    char cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    return system(cmd) == 0;
}

#endif
