/* fuzz_input.h: what every fuzz target shares.
 *
 * The loaders take paths, so each input is written to a file in a private
 * directory (on /dev/shm when there is one: no disk traffic) and loaded
 * from there. A finding is anything that is not a clean refusal: a crash or
 * sanitizer report, or a failure that is not one line naming the file,
 * which the targets turn into abort(). */
#ifndef WS_FUZZ_INPUT_H
#define WS_FUZZ_INPUT_H
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include "nn/base/status.h"
#include "base/runtime.h"

/* The private directory of this process, made by fuzz_setup(). */
static char fuzz_dir[256];

static void fuzz_cleanup(void) {
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", fuzz_dir);
    if (system(cmd) != 0) fprintf(stderr, "fuzz: cannot remove %s\n", fuzz_dir);
}

/* Makes the private directory, removed again when the fuzzer exits (one
 * that crashed leaves it, with the input beside the crash report). */
static void fuzz_setup(const char *target) {
    struct stat sb;
    const char *base = stat("/dev/shm", &sb) == 0 && S_ISDIR(sb.st_mode) ? "/dev/shm" : "/tmp";
    snprintf(fuzz_dir, sizeof fuzz_dir, "%s/ws_fuzz_%s_XXXXXX", base, target);
    if (!mkdtemp(fuzz_dir)) abort();
    atexit(fuzz_cleanup);
    ws_status st = {0};
    if (ws_runtime_init(1, &st)) abort();
}

/* Writes data to fuzz_dir/name; the full path goes to path (4096 bytes). */
static void fuzz_write(const char *name, const uint8_t *data, size_t size, char *path) {
    snprintf(path, 4096, "%s/%s", fuzz_dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, size, f) != size || fclose(f) != 0) abort();
}

/* For formats ending in a crc32 of everything before it: stores the right
 * checksum in the last 4 bytes, so that mutations reach the parser behind
 * the check instead of all failing at it (the check itself is covered by
 * the unit and regression tests). Returns a copy to free. */
static inline uint8_t *fuzz_fix_crc(const uint8_t *data, size_t size) {
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy) abort();
    memcpy(copy, data, size);
    if (size >= 4) {
        uint32_t crc = (uint32_t)crc32(0L, copy, (uInt)(size - 4));
        for (int i = 0; i < 4; i++) copy[size - 4 + i] = (uint8_t)(crc >> (8 * i));
    }
    return copy;
}

/* A clean refusal: the expected code and one line that starts with the
 * name of the file (or directory) it is about. */
static void fuzz_expect_refusal(const ws_status *st, int code, const char *about) {
    if (st->code != code || strncmp(st->msg, about, strlen(about)) != 0 || strchr(st->msg, '\n')) {
        fprintf(stderr, "fuzz: not a clean refusal (code %d, expected %d): %s\n", st->code, code,
                st->msg);
        abort();
    }
}

#endif
