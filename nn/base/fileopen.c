/* fileopen.c: checked opens of user paths (see fileopen.h). */
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "fileopen.h"

int ws_open_regular(const char *path, uint64_t max_bytes, int *fd, uint64_t *bytes,
                    ws_status *st) {
    *fd = -1;
    *bytes = 0;
    /* stat first, so that a device is not even opened (opening one can have
     * effects: a tape rewinds, a terminal becomes the controlling one);
     * fstat after the open decides, should the path change in between */
    struct stat sb;
    if (stat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
        return ws_fail(st, WS_EINPUT, "%s: not a regular file", path);
    int f = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (f < 0) return ws_fail(st, WS_EINPUT, "%s: cannot open: %s", path, strerror(errno));
    int flags;
    if (fstat(f, &sb) != 0) {
        ws_fail(st, WS_EIO, "%s: cannot stat: %s", path, strerror(errno));
    } else if (!S_ISREG(sb.st_mode)) {
        ws_fail(st, WS_EINPUT, "%s: not a regular file", path);
    } else if ((uint64_t)sb.st_size > max_bytes) {
        ws_fail(st, WS_EINPUT, "%s: larger than %llu bytes", path, (unsigned long long)max_bytes);
    } else if ((flags = fcntl(f, F_GETFL)) < 0 || fcntl(f, F_SETFL, flags & ~O_NONBLOCK) < 0) {
        ws_fail(st, WS_EIO, "%s: cannot set blocking mode: %s", path, strerror(errno));
    } else {
        *fd = f;
        *bytes = (uint64_t)sb.st_size;
        return WS_OK;
    }
    close(f);
    return st->code;
}

int ws_fopen_regular(const char *path, uint64_t max_bytes, FILE **fp, ws_status *st) {
    *fp = NULL;
    int fd;
    uint64_t bytes;
    if (ws_open_regular(path, max_bytes, &fd, &bytes, st)) return st->code;
    *fp = fdopen(fd, "rb");
    if (!*fp) {
        int err = errno;
        close(fd);
        return ws_fail(st, WS_ENOMEM, "%s: cannot open a stream: %s", path, strerror(err));
    }
    return WS_OK;
}
