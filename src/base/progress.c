/* progress.c: a long step's progress line (see progress.h). */
#include "base/progress.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "base/timing.h"

void ws_clock_text(double seconds, char text[32]) {
    long t = (long)(seconds + 0.5);
    snprintf(text, 32, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
}

void ws_progress_text(const char *what, const char *unit, long done, long total, double spent, int final,
                      char *text, size_t size) {
    char spent_text[32], left_text[32];
    ws_clock_text(spent, spent_text);
    if (final) {
        snprintf(text, size, "%s: %ld %s in %s", what, done, unit, spent_text);
    } else if (total > 0 && done > 0) {
        /* the units so far at their mean pace: a step of like units (views,
         * slices of a grid) is as honest about its rest as it can be */
        ws_clock_text(spent * (double)(total - done) / (double)done, left_text);
        snprintf(text, size, "%s: %ld of %ld %s, %s spent, about %s left", what, done, total, unit, spent_text,
                 left_text);
    } else if (total > 0) {
        snprintf(text, size, "%s: 0 of %ld %s, %s spent", what, total, unit, spent_text);
    } else {
        snprintf(text, size, "%s: %ld %s, %s spent", what, done, unit, spent_text);
    }
}

void ws_progress_init(ws_progress *p) {
    memset(p, 0, sizeof *p);
    p->tty = isatty(STDERR_FILENO);
}

void ws_progress_begin(ws_progress *p, const char *what, const char *unit, long total) {
    if (!p) return;
    snprintf(p->what, sizeof p->what, "%s", what);
    p->unit = unit;
    p->total = total > 0 ? total : 0;
    p->done = 0;
    p->start = p->last = ws_seconds();
    p->written = 0;
}

/* Writes the step's line now (the caller holds the critical section). */
static void write_line(ws_progress *p, double now, int final) {
    char text[256];
    ws_progress_text(p->what, p->unit, p->done, p->total, now - p->start, final, text, sizeof text);
    /* the spaces clear what a longer line before left on a terminal */
    fprintf(stderr, p->tty ? "\r%s   %s" : "%s%s\n", text, p->tty && final ? "\n" : "");
    fflush(stderr);
    p->last = now;
    p->written++;
}

void ws_progress_advance(ws_progress *p, long units) {
    if (!p) return;
    #pragma omp critical(ws_progress)
    {
        p->done += units;
        double now = ws_seconds();
        if (now - p->last >= (p->tty ? WS_PROGRESS_TTY_SECONDS : WS_PROGRESS_LOG_SECONDS)) write_line(p, now, 0);
    }
}

void ws_progress_end(ws_progress *p) {
    if (!p || !p->written) return;
    write_line(p, ws_seconds(), 1);
}
