/* test_unit_plan.c: the split of a batch over MPI ranks
 * (objective/unit_plan.h), checked as plain arithmetic for 1..64 ranks,
 * batches of 0..9 views and 1..6 passes per view, against what the
 * exchange of objective.c relies on:
 * - every unit is computed by exactly one rank, each rank's in one range;
 * - a view's owner computes its first unit;
 * - a rank sends only part of the first view it touches, to that view's
 *   owner, receives only the last it touches, and never the same view;
 * - what the owner of a view receives from each rank is exactly what that
 *   rank computed of it and sends it, and together with its own passes
 *   covers the view once;
 * - the view a rank sends and the one it receives are in different item
 *   slots, and every view a rank finishes at once is whole on it. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "objective/unit_plan.h"

static int empty(ws_pass_range r) { return r.begin >= r.end; }

/* Checks the plans of all N ranks for V views of P passes; returns the
 * number of failed properties (each also counted by CHECK once). */
static int check_plans(ws_unit_plan *plans, int N, int V, int P) {
    int bad = 0;
    for (int r = 0; r < N; r++) ws_unit_plan_make(&plans[r], V, P);
    int *count = calloc((size_t)V * P + 1, sizeof *count);
    for (int k = 0; k < V; k++) {
        int owner = ws_unit_plan_owner(&plans[0], k);
        for (int r = 1; r < N; r++) bad += ws_unit_plan_owner(&plans[r], k) != owner;
        ws_pass_range own = ws_unit_plan_computes(&plans[owner], k);
        bad += own.begin != 0 || empty(own); /* the owner computes the first unit */
        int covered = own.end - own.begin;
        for (int r = 0; r < N; r++) {
            ws_pass_range c = ws_unit_plan_computes(&plans[r], k);
            for (int p = c.begin; p < c.end; p++) count[k * P + p]++;
            if (r == owner || empty(c)) continue;
            /* another rank's part: it sends exactly that, the owner expects it */
            const ws_unit_plan *s = &plans[r], *o = &plans[owner];
            bad += s->send_view != k || s->send_to != owner || s->send.begin != c.begin || s->send.end != c.end;
            bad += o->recv_view != k || o->recv[r].begin != c.begin || o->recv[r].end != c.end;
            bad += ws_unit_plan_slot(s, k) != 0; /* the first view it touches */
            covered += c.end - c.begin;
        }
        bad += covered != P;
        if (own.end < P) bad += plans[owner].recv_view != k;
    }
    for (int u = 0; u < V * P; u++) bad += count[u] != 1;
    for (int r = 0; r < N; r++) {
        const ws_unit_plan *p = &plans[r];
        bad += p->send_view >= 0 && p->send_view == p->recv_view;
        /* a rank that sends and receives keeps the two in different slots */
        if (p->send_view >= 0 && p->recv_view >= 0)
            bad += ws_unit_plan_slot(p, p->send_view) == ws_unit_plan_slot(p, p->recv_view);
        /* it receives only from ranks that send it that view */
        for (int q = 0; q < N; q++)
            if (!empty(p->recv[q])) bad += q == r || plans[q].send_view != p->recv_view || plans[q].send_to != r;
        /* a view it neither sends nor receives is whole on it */
        for (int k = 0; k < V; k++) {
            ws_pass_range c = ws_unit_plan_computes(p, k);
            if (!empty(c) && k != p->send_view && k != p->recv_view) bad += c.begin != 0 || c.end != P;
        }
    }
    free(count);
    return bad;
}

int main(void) {
    ws_status st = {0};
    int total = 0, bad = 0, worst_n = 0, worst_v = 0, worst_p = 0;
    for (int N = 1; N <= 64; N++) {
        ws_unit_plan *plans = calloc((size_t)N, sizeof *plans);
        for (int r = 0; r < N; r++)
            if (ws_unit_plan_init(&plans[r], N, r, &st)) return 1;
        for (int V = 0; V <= 9; V++)
            for (int P = 1; P <= 6; P++, total++) {
                int b = check_plans(plans, N, V, P);
                if (b && !bad) worst_n = N, worst_v = V, worst_p = P;
                bad += b;
            }
        for (int r = 0; r < N; r++) ws_unit_plan_free(&plans[r]);
        free(plans);
    }
    CHECK(bad == 0, "%d broken properties over %d plans (first: %d ranks, %d views, %d passes)", bad, total, worst_n,
          worst_v, worst_p);
    /* One case spelled out: 3 ranks, 2 views of 4 passes (8 units: 0-1, 2-4, 5-7). */
    ws_unit_plan p[3];
    for (int r = 0; r < 3; r++) ws_unit_plan_init(&p[r], 3, r, &st), ws_unit_plan_make(&p[r], 2, 4);
    CHECK(p[0].send_view == -1 && p[0].recv_view == 0 && p[0].recv[1].begin == 2 && p[0].recv[1].end == 4,
          "rank 0 owns view 0 and receives its passes 2-3 from rank 1");
    CHECK(p[1].send_view == 0 && p[1].send_to == 0 && p[1].recv_view == 1 && p[1].recv[2].begin == 1 &&
              p[1].recv[2].end == 4,
          "rank 1 sends view 0's passes to rank 0 and receives view 1's passes 1-3 from rank 2");
    CHECK(p[2].send_view == 1 && p[2].send_to == 1 && p[2].recv_view == -1, "rank 2 sends its part of view 1");
    for (int r = 0; r < 3; r++) ws_unit_plan_free(&p[r]);
    return check_summary();
}
