/* adam.h: the Adam optimiser over the control points (double precision).
 * The state is plain data so that checkpoints save and restore it exactly. */
#ifndef WS_ADAM_H
#define WS_ADAM_H
#include "nn/base/status.h"

typedef struct {
    int n;              /* parameters */
    long step;          /* updates taken so far */
    double lr, beta1, beta2, eps;
    double *m, *v;      /* first and second moment estimates, n each */
} ws_adam;

int ws_adam_init(ws_adam *a, int n, double lr, ws_status *st);
void ws_adam_free(ws_adam *a);
/* One update of params from grad (both n). The caller has checked grad is
 * finite: a non-finite gradient must never reach the moments. Returns 0
 * when the new moments and params are finite, 1 when a finite but huge
 * gradient overflowed them (its square past 1e308): the caller undoes the
 * update, so that the state, and a checkpoint of it, stays finite. */
int ws_adam_update(ws_adam *a, double *params, const double *grad);

#endif
