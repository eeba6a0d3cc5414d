/* outfile.c: write-to-temporary-then-rename output files (see outfile.h).
 *
 * The registry of live temporary files is a fixed array of slots, each
 * claimed and released with atomic operations (writers run in parallel:
 * scene rendering writes one PNG per thread), so that a signal handler can
 * walk it and unlink what it names without locks or allocation. A slot is
 * claimed before the file is created and released after it was renamed or
 * removed, so the handler may unlink a name that no longer exists (harmless)
 * but never misses a file. With every slot taken a file is still written,
 * only not removed on a signal. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "base/outfile.h"

enum { LIVE_SLOTS = 256, SLOT_FREE = 0, SLOT_FILLING = 1, SLOT_LIVE = 2 };
static atomic_int live_state[LIVE_SLOTS];
static char live_tmp[LIVE_SLOTS][sizeof ((ws_outfile *)0)->tmp];

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

void ws_outfile_remove_live(void) {
    for (int i = 0; i < LIVE_SLOTS; i++)
        if (atomic_load(&live_state[i]) == SLOT_LIVE) unlink(live_tmp[i]);
}

static void remove_live_and_die(int sig) {
    ws_outfile_remove_live();
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

/* The PID of a temporary file's name, NAME.tmp.PID; 0 if it is not one. */
static long tmp_pid(const char *name) {
    const char *at = NULL;
    for (const char *p = strstr(name, ".tmp."); p; p = strstr(p + 1, ".tmp.")) at = p;
    if (!at || at == name || !at[5] || strlen(at + 5) > 9) return 0;
    for (const char *c = at + 5; *c; c++)
        if (*c < '0' || *c > '9') return 0;
    return atol(at + 5);
}

/* Removes the stale temporary files of `dir`: regular files NAME.tmp.PID
 * whose PID is no running process (kill(PID, 0) fails with ESRCH). A live
 * PID, even a reused one, keeps its file: nothing of a running writer is
 * ever touched. Each directory is swept once per process. */
static void sweep_stale(const char *path) {
    char dir[sizeof ((ws_outfile *)0)->path];
    const char *slash = strrchr(path, '/');
    if (!slash)
        strcpy(dir, ".");
    else
        snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path), path);
    enum { SWEPT_MAX = 64 };
    static char swept[SWEPT_MAX][sizeof dir];
    static int nswept;
    int fresh = 1;
#pragma omp critical(ws_outfile_sweep)
    {
        for (int i = 0; i < nswept && fresh; i++) fresh = strcmp(swept[i], dir) != 0;
        if (fresh && nswept < SWEPT_MAX) strcpy(swept[nswept++], dir);
    }
    DIR *d = fresh ? opendir(dir) : NULL;
    if (!d) return;
    long self = (long)getpid();
    for (struct dirent *e; (e = readdir(d));) {
        long pid = tmp_pid(e->d_name);
        struct stat sb;
        if (pid > 0 && pid != self && kill((pid_t)pid, 0) != 0 && errno == ESRCH &&
            fstatat(dirfd(d), e->d_name, &sb, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(sb.st_mode))
            unlinkat(dirfd(d), e->d_name, 0);
    }
    closedir(d);
}

int ws_outfile_open(ws_outfile *f, const char *path, ws_status *st) {
    f->fp = NULL;
    f->live = -1;
    if (strlen(path) >= sizeof f->path)
        return ws_fail(st, WS_EUSAGE, "%s: output path too long", path);
    strcpy(f->path, path);
    snprintf(f->tmp, sizeof f->tmp, "%s.tmp.%ld", path, (long)getpid());
    sweep_stale(path);
    f->live = live_add(f->tmp);
    f->fp = fopen(f->tmp, "wb");
    if (!f->fp) {
        int err = errno;
        live_release(f);
        return ws_fail(st, WS_EIO, "%s: cannot write: %s", path, strerror(err));
    }
    return WS_OK;
}

int ws_outfile_commit(ws_outfile *f, ws_status *st) {
    int failed = ferror(f->fp) || fflush(f->fp) != 0;
    int err = errno;
    if (!failed && fsync(fileno(f->fp)) != 0 && errno != EINVAL) {
        failed = 1;
        err = errno;
    }
    if (fclose(f->fp) != 0 && !failed) {
        failed = 1;
        err = errno;
    }
    f->fp = NULL;
    if (!failed && rename(f->tmp, f->path) != 0) {
        failed = 1;
        err = errno;
    }
    if (failed) unlink(f->tmp);
    live_release(f);
    return failed ? ws_fail(st, WS_EIO, "%s: write failed: %s", f->path, strerror(err ? err : EIO))
                  : WS_OK;
}

void ws_outfile_abort(ws_outfile *f) {
    if (f->fp) fclose(f->fp);
    f->fp = NULL;
    unlink(f->tmp);
    live_release(f);
}

int ws_mkdir(const char *dir, ws_status *st) {
    if (mkdir(dir, 0777) == 0 || errno == EEXIST) {
        struct stat sb;
        if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode)) return WS_OK;
        return ws_fail(st, WS_EIO, "%s: exists and is not a directory", dir);
    }
    return ws_fail(st, WS_EIO, "%s: cannot create directory: %s", dir, strerror(errno));
}
