/* outfile.c: write-to-temporary-then-rename output files (see outfile.h). */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "base/outfile.h"

int ws_outfile_open(ws_outfile *f, const char *path, ws_status *st) {
    f->fp = NULL;
    if (strlen(path) >= sizeof f->path)
        return ws_fail(st, WS_EUSAGE, "%s: output path too long", path);
    strcpy(f->path, path);
    snprintf(f->tmp, sizeof f->tmp, "%s.tmp.%ld", path, (long)getpid());
    f->fp = fopen(f->tmp, "wb");
    if (!f->fp) return ws_fail(st, WS_EIO, "%s: cannot write: %s", path, strerror(errno));
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
    if (failed) {
        unlink(f->tmp);
        return ws_fail(st, WS_EIO, "%s: write failed: %s", f->path, strerror(err ? err : EIO));
    }
    return WS_OK;
}

void ws_outfile_abort(ws_outfile *f) {
    if (f->fp) fclose(f->fp);
    f->fp = NULL;
    unlink(f->tmp);
}

int ws_mkdir(const char *dir, ws_status *st) {
    if (mkdir(dir, 0777) == 0 || errno == EEXIST) {
        struct stat sb;
        if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode)) return WS_OK;
        return ws_fail(st, WS_EIO, "%s: exists and is not a directory", dir);
    }
    return ws_fail(st, WS_EIO, "%s: cannot create directory: %s", dir, strerror(errno));
}
