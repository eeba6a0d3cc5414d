/* fit_state.c: the state of a fit (see fit_state.h). */
#include <stdlib.h>
#include <string.h>
#include "base/timing.h"
#include "fit/fit_state.h"

void ws_fit_state_free(ws_fit_state *s) {
    free(s->order);
    ws_curves_free(&s->curves);
    ws_adam_free(&s->adam);
    free(s->log);
    free(s->snapshots);
    memset(s, 0, sizeof *s);
}

int ws_fit_state_log(ws_fit_state *s, const ws_log_row *row, ws_status *st) {
    if (s->nlog == s->caplog) {
        int cap = s->caplog ? 2 * s->caplog : 1024;
        ws_log_row *grown = realloc(s->log, (size_t)cap * sizeof *grown);
        if (!grown) return ws_fail(st, WS_ENOMEM, "out of memory growing the training log");
        s->log = grown;
        s->caplog = cap;
    }
    s->log[s->nlog++] = *row;
    return WS_OK;
}

int ws_fit_state_snapshot(ws_fit_state *s, ws_status *st) {
    size_t np = (size_t)s->curves.n * WS_CURVE_FLOATS;
    if (s->nsnap == s->capsnap) {
        int cap = s->capsnap ? 2 * s->capsnap : 64;
        double *grown = realloc(s->snapshots, (size_t)cap * np * sizeof(double));
        if (!grown) return ws_fail(st, WS_ENOMEM, "out of memory keeping curve snapshots");
        s->snapshots = grown;
        s->capsnap = cap;
    }
    memcpy(s->snapshots + (size_t)s->nsnap++ * np, s->curves.P, np * sizeof(double));
    return WS_OK;
}

double ws_fit_state_elapsed(const ws_fit_state *s, double start) {
    return s->elapsed + ws_seconds() - start;
}
