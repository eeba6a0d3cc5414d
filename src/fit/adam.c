/* adam.c: Adam (Kingma & Ba), as torch.optim.Adam with default betas. */
#include <math.h>
#include <stdlib.h>
#include "fit/adam.h"

int ws_adam_init(ws_adam *a, int n, double lr, ws_status *st) {
    a->n = n;
    a->step = 0;
    a->lr = lr;
    a->beta1 = 0.9;
    a->beta2 = 0.999;
    a->eps = 1e-8;
    a->m = ws_calloc((size_t)n, sizeof(double), "Adam moments", st);
    a->v = a->m ? ws_calloc((size_t)n, sizeof(double), "Adam moments", st) : NULL;
    if (!a->v) {
        free(a->m);
        a->m = NULL;
        return st->code;
    }
    return WS_OK;
}

void ws_adam_free(ws_adam *a) {
    free(a->m);
    free(a->v);
    a->m = a->v = NULL;
}

int ws_adam_update(ws_adam *a, double *params, const double *grad) {
    a->step++;
    double bias1 = 1.0 - pow(a->beta1, (double)a->step);
    double bias2 = 1.0 - pow(a->beta2, (double)a->step);
    int overflow = 0;
    for (int i = 0; i < a->n; i++) {
        a->m[i] = a->beta1 * a->m[i] + (1.0 - a->beta1) * grad[i];
        a->v[i] = a->beta2 * a->v[i] + (1.0 - a->beta2) * grad[i] * grad[i];
        double mhat = a->m[i] / bias1;
        double vhat = a->v[i] / bias2;
        params[i] -= a->lr * mhat / (sqrt(vhat) + a->eps);
        overflow |= !isfinite(a->v[i]) || !isfinite(params[i]);
    }
    return overflow;
}
