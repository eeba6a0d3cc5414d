/* outfile.c: write-to-temporary-then-rename output files (see outfile.h).
 *
 * The registry of live temporary files is a fixed array of slots, each
 * claimed and released with atomic operations (writers run in parallel:
 * scene rendering writes one PNG per thread), so that a signal handler can
 * walk it and unlink what it names without locks or allocation. A slot is
 * claimed before the file is created and released after it was renamed or
 * removed, so the handler may unlink a name that no longer exists (harmless)
 * but never misses a file. With every slot taken a file is still written,
 * only not removed on a signal.
 *
 * Temporary names carry a prefix of the program's own, its PID and a
 * counter: a user's file never has such a name by accident (notes.tmp.2024
 * does not), so the stale-file sweep removes only what a run of this
 * program left, and a name taken by anything already there (a planted
 * link) is skipped, never opened. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "base/outfile.h"

#define TMP_PREFIX ".wiresketch.tmp."
/* bytes of the target's name kept in the temporary name (NAME_MAX is 255) */
#define TMP_NAME_KEEP 200

enum { LIVE_SLOTS = 256, SLOT_FREE = 0, SLOT_FILLING = 1, SLOT_LIVE = 2 };
static atomic_int live_state[LIVE_SLOTS];
static char live_tmp[LIVE_SLOTS][sizeof ((ws_outfile *)0)->tmp];
static atomic_uint tmp_counter;

static int live_add(const char *tmp) {
    for (int i = 0; i < LIVE_SLOTS; i++) {
        int expected = SLOT_FREE;
        if (atomic_compare_exchange_strong(&live_state[i], &expected, SLOT_FILLING)) {
            strcpy(live_tmp[i], tmp);
            atomic_store(&live_state[i], SLOT_LIVE);
            return i;
        }
    }
    return -1;
}

static void live_release(ws_outfile *f) {
    if (f->live >= 0) atomic_store(&live_state[f->live], SLOT_FREE);
    f->live = -1;
}

/* Removes every live temporary file; async-signal-safe. */
static void remove_live(void) {
    for (int i = 0; i < LIVE_SLOTS; i++)
        if (atomic_load(&live_state[i]) == SLOT_LIVE) unlink(live_tmp[i]);
}

static void remove_live_and_die(int sig) {
    remove_live();
    raise(sig); /* SA_RESETHAND: the default action, once this handler returns */
}

void ws_outfile_remove_on_signals(void) {
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = remove_live_and_die;
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
    sigaction(SIGXCPU, &sa, NULL);
}

/* ---------------------------------------------------------------- inputs */

typedef struct {
    dev_t dev;
    ino_t ino;
    int is_dir;
    char path[WS_PATH_MAX]; /* as the user spelled it, for messages */
} input_id;
static input_id inputs[WS_OUTFILE_MAX_INPUTS];
static int ninputs;

/* A file input named as a folder (a wrong --init) protects only itself:
 * its reader refuses it, and what lies inside is no input. */
int ws_outfile_protect(const char *const *files, int nfiles, const char *const *folders, int nfolders,
                       ws_status *st) {
    ninputs = 0;
    for (int k = 0; k < nfiles + nfolders; k++) {
        const char *path = k < nfiles ? files[k] : folders[k - nfiles];
        struct stat sb;
        if (!path || stat(path, &sb) != 0) continue;
        if (ninputs == WS_OUTFILE_MAX_INPUTS)
            return ws_fail(st, WS_EUSAGE, "%s: more than %d inputs", path, WS_OUTFILE_MAX_INPUTS);
        input_id *in = &inputs[ninputs++];
        in->dev = sb.st_dev;
        in->ino = sb.st_ino;
        in->is_dir = k >= nfiles && S_ISDIR(sb.st_mode);
        snprintf(in->path, sizeof in->path, "%s", path);
    }
    return WS_OK;
}

/* dir of `path` (without trailing slashes) into dir: "." for a bare name. */
static void parent_of(const char *path, char *dir, size_t size) {
    size_t n = strlen(path);
    while (n > 1 && path[n - 1] == '/') n--;
    while (n > 0 && path[n - 1] != '/') n--;
    while (n > 1 && path[n - 1] == '/') n--;
    if (n == 0)
        snprintf(dir, size, ".");
    else
        snprintf(dir, size, "%.*s", (int)n, path);
}

/* Refuses `path` as an output when it is an input (a file or folder of
 * ws_outfile_protect) or lies inside an input folder: the folder its files
 * go to (the folder itself, a link to one followed; for a file, the folder
 * that holds its name) and every folder above it (F/.., F/../.., ... as the
 * kernel resolves them, up to the root) are compared with the input
 * folders by identity. */
int ws_outfile_check(const char *path, ws_status *st) {
    if (!ninputs) return WS_OK;
    struct stat sb;
    int is_dir = 0;
    if (stat(path, &sb) == 0) {
        for (int k = 0; k < ninputs; k++)
            if (sb.st_dev == inputs[k].dev && sb.st_ino == inputs[k].ino)
                return ws_fail(st, WS_EUSAGE, "%s: is %s, which this command reads; choose another output",
                               path, inputs[k].path);
        is_dir = S_ISDIR(sb.st_mode);
    }
    static _Thread_local char walk[4 * WS_PATH_MAX];
    if (is_dir)
        snprintf(walk, sizeof walk, "%s/..", path);
    else
        parent_of(path, walk, sizeof walk);
    dev_t last_dev = 0;
    ino_t last_ino = 0;
    for (int depth = 0; stat(walk, &sb) == 0; depth++) {
        if (depth && sb.st_dev == last_dev && sb.st_ino == last_ino) break; /* the root: its own parent */
        for (int k = 0; k < ninputs; k++)
            if (inputs[k].is_dir && sb.st_dev == inputs[k].dev && sb.st_ino == inputs[k].ino)
                return ws_fail(st, WS_EUSAGE,
                               "%s: lies inside %s, which this command reads; choose an output outside it", path,
                               inputs[k].path);
        last_dev = sb.st_dev;
        last_ino = sb.st_ino;
        size_t n = strlen(walk);
        if (n + 4 > sizeof walk) break;
        strcpy(walk + n, "/..");
    }
    return WS_OK;
}

/* ---------------------------------------------------------------- stale */

/* The PID of one of this program's temporary names,
 * .wiresketch.tmp.PID.N.NAME (a PID of at most 9 digits fits a pid_t); 0
 * if `name` is not one. */
static long tmp_pid(const char *name) {
    size_t prefix = strlen(TMP_PREFIX);
    if (strncmp(name, TMP_PREFIX, prefix)) return 0;
    const char *c = name + prefix;
    long pid = 0;
    int digits = 0;
    for (; *c >= '0' && *c <= '9' && digits < 9; c++, digits++) pid = 10 * pid + (*c - '0');
    if (!digits || *c++ != '.') return 0;
    for (digits = 0; *c >= '0' && *c <= '9'; c++) digits++;
    return digits && c[0] == '.' && c[1] ? pid : 0;
}

/* Removes the stale temporary files of `dir`: regular files of this user
 * with this program's temporary names whose PID is no running process
 * (kill(PID, 0) fails with ESRCH). A live PID, even a reused one, keeps its
 * file: nothing of a running writer is ever touched. Each directory is
 * swept once per process. */
static void sweep_stale(const char *dir) {
    enum { SWEPT_MAX = 64 };
    static char swept[SWEPT_MAX][WS_PATH_MAX];
    static int nswept;
    int fresh = 1;
#pragma omp critical(ws_outfile_sweep)
    {
        for (int i = 0; i < nswept && fresh; i++) fresh = strcmp(swept[i], dir) != 0;
        if (fresh && nswept < SWEPT_MAX) snprintf(swept[nswept++], WS_PATH_MAX, "%s", dir);
    }
    DIR *d = fresh ? opendir(dir) : NULL;
    if (!d) return;
    long self = (long)getpid();
    uid_t me = geteuid();
    for (struct dirent *e; (e = readdir(d));) {
        long pid = tmp_pid(e->d_name);
        struct stat sb;
        if (pid > 0 && pid != self && kill((pid_t)pid, 0) != 0 && errno == ESRCH &&
            fstatat(dirfd(d), e->d_name, &sb, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(sb.st_mode) &&
            sb.st_uid == me)
            unlinkat(dirfd(d), e->d_name, 0);
    }
    closedir(d);
}

/* ---------------------------------------------------------------- open */

/* Is `path` one of the process's descriptors (/dev/stdout, /dev/fd/N,
 * /proc/self/fd/N)? Replacing one would replace the link, not write to
 * what it stands for. */
static int is_descriptor(const char *path) {
    char link[16], dir[WS_PATH_MAX], real[PATH_MAX];
    ssize_t n = readlink(path, link, sizeof link - 1);
    if (n >= 6 && !strncmp(link, "/proc/", 6)) return 1;
    parent_of(path, dir, sizeof dir);
    return realpath(dir, real) && !strncmp(real, "/proc/", 6);
}

/* Writes through an existing special file or descriptor: no temporary
 * file, nothing to rename; appended to, so that a file behind /dev/stdout
 * keeps what the shell or an earlier writer put there. */
static int open_through(ws_outfile *f, ws_status *st) {
    int fd = open(f->path, O_WRONLY | O_APPEND | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) return ws_fail(st, WS_EIO, "%s: cannot write: %s", f->path, strerror(errno));
    if (!(f->fp = fdopen(fd, "wb"))) {
        close(fd);
        return ws_fail(st, WS_ENOMEM, "%s: out of memory opening it", f->path);
    }
    return WS_OK;
}

int ws_outfile_open(ws_outfile *f, const char *path, ws_status *st) {
    f->fp = NULL;
    f->live = -1;
    f->tmp[0] = '\0';
    if (strlen(path) >= sizeof f->path)
        return ws_fail(st, WS_EUSAGE, "%s: output path too long", path);
    strcpy(f->path, path);
    if (ws_outfile_check(path, st)) return st->code;
    struct stat sb;
    if (stat(path, &sb) == 0) {
        if (S_ISDIR(sb.st_mode)) return ws_fail(st, WS_EIO, "%s: is a directory", path);
        if (S_ISBLK(sb.st_mode))
            return ws_fail(st, WS_EIO, "%s: is a block device; refusing to write onto it", path);
        if (!S_ISREG(sb.st_mode) || is_descriptor(path)) return open_through(f, st);
    }
    char dir[WS_PATH_MAX];
    parent_of(path, dir, sizeof dir);
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    if (!*name) return ws_fail(st, WS_EUSAGE, "%s: output path names no file", path);
    sweep_stale(dir);
    /* a name already taken (by anything: a file, a planted link) is left
     * alone and the next one tried */
    for (int attempt = 0; attempt < 100; attempt++) {
        unsigned n = atomic_fetch_add(&tmp_counter, 1);
        int len = snprintf(f->tmp, sizeof f->tmp, "%.*s" TMP_PREFIX "%ld.%u.%.*s", (int)(name - path), path,
                           (long)getpid(), n, TMP_NAME_KEEP, name);
        if (len < 0 || (size_t)len >= sizeof f->tmp)
            return ws_fail(st, WS_EUSAGE, "%s: output path too long", path);
        f->live = live_add(f->tmp);
        int fd = open(f->tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd >= 0 && (f->fp = fdopen(fd, "wb"))) return WS_OK;
        int err = fd >= 0 ? ENOMEM : errno;
        if (fd >= 0) {
            close(fd);
            unlink(f->tmp);
        }
        live_release(f);
        f->tmp[0] = '\0';
        if (err != EEXIST) return ws_fail(st, WS_EIO, "%s: cannot write: %s", path, strerror(err));
    }
    return ws_fail(st, WS_EIO, "%s: cannot write: 100 temporary names beside it are taken", path);
}

int ws_outfile_commit(ws_outfile *f, ws_status *st) {
    int failed = ferror(f->fp) || fflush(f->fp) != 0;
    int err = errno;
    if (!failed && f->tmp[0] && fsync(fileno(f->fp)) != 0 && errno != EINVAL) {
        failed = 1;
        err = errno;
    }
    if (fclose(f->fp) != 0 && !failed) {
        failed = 1;
        err = errno;
    }
    f->fp = NULL;
    if (!failed && f->tmp[0] && rename(f->tmp, f->path) != 0) {
        failed = 1;
        err = errno;
    }
    if (failed && f->tmp[0]) unlink(f->tmp);
    live_release(f);
    return failed ? ws_fail(st, WS_EIO, "%s: write failed: %s", f->path, strerror(err ? err : EIO))
                  : WS_OK;
}

void ws_outfile_abort(ws_outfile *f) {
    if (f->fp) fclose(f->fp);
    f->fp = NULL;
    if (f->tmp[0]) unlink(f->tmp);
    live_release(f);
}

int ws_mkdir(const char *dir, ws_status *st) {
    if (ws_outfile_check(dir, st)) return st->code;
    if (mkdir(dir, 0777) == 0 || errno == EEXIST) {
        struct stat sb;
        if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode)) return WS_OK;
        return ws_fail(st, WS_EIO, "%s: exists and is not a directory", dir);
    }
    return ws_fail(st, WS_EIO, "%s: cannot create directory: %s", dir, strerror(errno));
}

int ws_mkdir_inside(const char *dir, ws_status *st) {
    struct stat sb;
    if (lstat(dir, &sb) == 0 && S_ISLNK(sb.st_mode))
        return ws_fail(st, WS_EIO, "%s: is a symbolic link; remove it (outputs are not written through a link here)",
                       dir);
    return ws_mkdir(dir, st);
}
