/* test_progress.c: a long step's progress line (base/progress.h): its
 * text, when a log gets a line (none for a short step, one when one is
 * due, a last one after it), the count from the threads of a parallel
 * loop; NULL is silent. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/progress.h"
#include "base/timing.h"
#include "check.h"

/* Runs the step f on a log (stderr into a file) and returns what it wrote. */
static char *logged(void (*f)(ws_progress *), char *text, size_t size) {
    char path[] = "/tmp/ws_test_progress_XXXXXX";
    int fd = mkstemp(path), saved = dup(STDERR_FILENO);
    fflush(stderr);
    dup2(fd, STDERR_FILENO);
    ws_progress p;
    ws_progress_init(&p);
    p.tty = 0; /* a log, whatever the test runs in */
    f(&p);
    fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    FILE *in = fdopen(fd, "r");
    rewind(in);
    size_t n = fread(text, 1, size - 1, in);
    text[n] = 0;
    fclose(in);
    unlink(path);
    return text;
}

static void short_step(ws_progress *p) {
    ws_progress_begin(p, "loading the photos", "views", 4);
    for (int k = 0; k < 4; k++) ws_progress_advance(p, 1);
    ws_progress_end(p);
}

/* A step whose third unit comes after the log's interval. */
static void long_step(ws_progress *p) {
    ws_progress_begin(p, "loading the photos", "views", 4);
    ws_progress_advance(p, 2);
    p->start -= 30; /* as if begun 30 s ago ... */
    p->last -= WS_PROGRESS_LOG_SECONDS + 1; /* ... and last written over the interval ago */
    ws_progress_advance(p, 1);
    ws_progress_advance(p, 1); /* not due again */
    ws_progress_end(p);
}

int main(void) {
    char text[512];
    ws_clock_text(3725.4, text);
    CHECK(!strcmp(text, "1:02:05"), "clock: %s", text);
    ws_clock_text(0.2, text);
    CHECK(!strcmp(text, "0:00:00"), "clock: %s", text);
    ws_progress_text("loading the photos", "views", 12, 64, 3.0, 0, text, sizeof text);
    CHECK(!strcmp(text, "loading the photos: 12 of 64 views, 0:00:03 spent, about 0:00:13 left"), "text: %s", text);
    ws_progress_text("loading the photos", "views", 0, 64, 1.0, 0, text, sizeof text);
    CHECK(!strcmp(text, "loading the photos: 0 of 64 views, 0:00:01 spent"), "nothing done yet: %s", text);
    ws_progress_text("carving the photo hull", "passes", 7, 0, 4.2, 0, text, sizeof text);
    CHECK(!strcmp(text, "carving the photo hull: 7 passes, 0:00:04 spent"), "unknown total: %s", text);
    ws_progress_text("loading the photos", "views", 64, 64, 16.0, 1, text, sizeof text);
    CHECK(!strcmp(text, "loading the photos: 64 views in 0:00:16"), "final: %s", text);

    CHECK(!strcmp(logged(short_step, text, sizeof text), ""), "a short step wrote to the log: %s", text);
    logged(long_step, text, sizeof text);
    CHECK(!strcmp(text, "loading the photos: 3 of 4 views, 0:00:30 spent, about 0:00:10 left\n"
                        "loading the photos: 4 views in 0:00:30\n"),
          "a long step's log: %s", text);

    /* the threads of a parallel loop add up; nothing is due on a log */
    ws_progress p;
    ws_progress_init(&p);
    p.tty = 0;
    ws_progress_begin(&p, "voting", "slices", 10000);
    #pragma omp parallel for
    for (int k = 0; k < 10000; k++) ws_progress_advance(&p, 1);
    CHECK(p.done == 10000 && p.written == 0, "parallel count %ld, %d lines", p.done, p.written);
    ws_progress_begin(&p, "voting", "slices", 3);
    CHECK(p.done == 0 && p.written == 0 && p.total == 3, "a new step starts at 0");

    /* NULL: silent (a library user's default) */
    ws_progress_begin(NULL, "x", "y", 1);
    ws_progress_advance(NULL, 1);
    ws_progress_end(NULL);
    return check_summary();
}
