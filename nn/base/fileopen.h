/* fileopen.h: the one way wiresketch opens a file whose path a user gave.
 *
 * A path may name a FIFO, a device or a directory: opening a FIFO for
 * reading blocks until a writer appears, and /dev/zero never ends. So the
 * path's type is checked with stat (a device is not even opened), the file
 * opened with O_NONBLOCK (which cannot block) and its type checked again
 * with fstat, anything but a regular file refused ("PATH: not a regular file"),
 * its size checked against the caller's cap, and only then is O_NONBLOCK
 * cleared for ordinary blocking reads. Every reader of user files (scenes,
 * images, curve files, point clouds, checkpoints, weight files) goes
 * through here. */
#ifndef WS_FILEOPEN_H
#define WS_FILEOPEN_H
#include <stdint.h>
#include <stdio.h>
#include "status.h"

/* Opens `path` read-only (O_CLOEXEC) if it is a regular file of at most
 * max_bytes; *fd and *bytes (its size) are set on success. */
int ws_open_regular(const char *path, uint64_t max_bytes, int *fd, uint64_t *bytes,
                    ws_status *st);

/* The same as a stdio stream ("rb"). */
int ws_fopen_regular(const char *path, uint64_t max_bytes, FILE **fp, ws_status *st);

#endif
