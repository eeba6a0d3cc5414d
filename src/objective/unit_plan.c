/* unit_plan.c: the split of a batch's units over ranks (see unit_plan.h). */
#include <stdlib.h>
#include "objective/unit_plan.h"

/* The first of U units that rank r takes, of N ranks. */
static long unit_start(long U, int r, int N) { return U * r / N; }

/* The units of [u0, u1) that rank r computes, as passes of the view that
 * starts at u0. */
static ws_pass_range overlap(const ws_unit_plan *p, long u0, long u1, int r) {
    long U = (long)p->views * p->passes, lo = unit_start(U, r, p->ranks), hi = unit_start(U, r + 1, p->ranks);
    long a = u0 > lo ? u0 : lo, b = u1 < hi ? u1 : hi;
    ws_pass_range range = {(int)(a - u0), (int)(b - u0)};
    if (a >= b) range.begin = range.end = 0;
    return range;
}

int ws_unit_plan_init(ws_unit_plan *plan, int ranks, int rank, ws_status *st) {
    *plan = (ws_unit_plan){.ranks = ranks, .rank = rank, .send_view = -1, .recv_view = -1};
    plan->recv = ws_calloc((size_t)ranks, sizeof *plan->recv, "unit plan", st);
    return plan->recv ? WS_OK : st->code;
}

void ws_unit_plan_free(ws_unit_plan *plan) {
    free(plan->recv);
    plan->recv = NULL;
}

void ws_unit_plan_make(ws_unit_plan *p, int views, long passes) {
    long U = (long)views * passes;
    p->views = views;
    p->passes = passes;
    p->lo = unit_start(U, p->rank, p->ranks);
    p->hi = unit_start(U, p->rank + 1, p->ranks);
    p->send_view = p->recv_view = -1;
    p->send_to = -1;
    p->send = (ws_pass_range){0, 0};
    for (int r = 0; r < p->ranks; r++) p->recv[r] = (ws_pass_range){0, 0};
    if (p->lo >= p->hi) return;
    int first = (int)(p->lo / passes), last = (int)((p->hi - 1) / passes);
    if (first * passes < p->lo) {
        p->send_view = first;
        p->send_to = ws_unit_plan_owner(p, first);
        p->send = overlap(p, first * passes, (first + 1) * passes, p->rank);
    }
    if ((last + 1) * passes > p->hi && last != p->send_view) {
        p->recv_view = last;
        for (int r = 0; r < p->ranks; r++)
            if (r != p->rank) p->recv[r] = overlap(p, last * passes, (last + 1) * passes, r);
    }
}

ws_pass_range ws_unit_plan_computes(const ws_unit_plan *p, int k) {
    return overlap(p, k * p->passes, (k + 1) * p->passes, p->rank);
}

int ws_unit_plan_owner(const ws_unit_plan *p, int k) {
    long U = (long)p->views * p->passes, u = k * p->passes;
    int N = p->ranks, r = (int)(u * N / U);
    while (r + 1 < N && unit_start(U, r + 1, N) <= u) r++;
    while (unit_start(U, r, N) > u) r--;
    return r;
}

int ws_unit_plan_slot(const ws_unit_plan *p, int k) { return k == p->lo / p->passes ? 0 : 1; }
