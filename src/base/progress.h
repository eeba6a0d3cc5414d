/* progress.h: how far a long step has come, as one line on stderr.
 *
 * A command shows its steps' progress this way: loading a capture's
 * photos, carving its photo hull, the views' vote. On a terminal the line
 * is rewritten in place every WS_PROGRESS_TTY_SECONDS and ends when the
 * step does; elsewhere (a log, a pipe) a line every WS_PROGRESS_LOG_SECONDS
 * and, when one was written, a last line with the step's time, so a short
 * step's log stays as it was and a long one shows that it moves.
 *
 * Everywhere a ws_progress pointer is optional: NULL is silent (a library
 * user's default, `--quiet`, every MPI rank but 0). ws_progress_advance may
 * be called from the threads of a parallel loop. */
#ifndef WS_PROGRESS_H
#define WS_PROGRESS_H
#include <stddef.h>

#define WS_PROGRESS_TTY_SECONDS 0.2
#define WS_PROGRESS_LOG_SECONDS 10.0

typedef struct {
    int tty;        /* stderr is a terminal */
    char what[96];  /* the step, as the line names it: "loading the photos" */
    const char *unit; /* what total counts: "views" */
    long total;     /* 0: unknown (the line then counts without a time left) */
    long done;
    double start, last; /* ws_seconds() at the step's start and at the last line */
    int written;    /* lines written for this step */
} ws_progress;

/* Sets tty from stderr; no step is under way. */
void ws_progress_init(ws_progress *p);

/* A new step of total units (total 0: as many as it takes). */
void ws_progress_begin(ws_progress *p, const char *what, const char *unit, long total);

/* units more of the step done; a line when one is due. */
void ws_progress_advance(ws_progress *p, long units);

/* The step is over: the terminal's line ends; in a log, a last line when
 * one was written. */
void ws_progress_end(ws_progress *p);

/* The line for done of total units after spent seconds, as written:
 *   "loading the photos: 12 of 64 views, 0:00:03 spent, about 0:00:13 left"
 *   "carving the photo hull: 7 passes, 0:00:04 spent" (total 0)
 *   "loading the photos: 64 views in 0:00:16" (final) */
void ws_progress_text(const char *what, const char *unit, long done, long total, double spent, int final,
                      char *text, size_t size);

/* h:mm:ss of a duration in seconds (text: at least 32 bytes). */
void ws_clock_text(double seconds, char text[32]);

#endif
