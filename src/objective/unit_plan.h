/* unit_plan.h: which part of a batch each rank of an MPI job computes,
 * owns, sends and receives (one rank otherwise: it computes and owns all).
 *
 * A batch of V views is cut into units of work: view k's CLIP passes
 * p = 0..P-1 (loss.h) are units k P + p (a view is one unit without CLIP,
 * and in an evaluation), and rank r of N computes units
 * [U r / N, U (r + 1) / N) of U = V P. The rank of a view's first unit owns
 * the view: it combines the view's items and carries dL/dalpha back to the
 * control points, so the passes other ranks computed of it are sent to it.
 * Ranges of consecutive units meet at most two views part-way: a rank
 * sends its part of the first view it touches when that view started on
 * an earlier rank, and receives the rest of the last view it touches when
 * that view goes on past its units; the two are never the same view. A
 * pass gives the same bits on any rank, so the batch has the bits of one
 * process for any number of ranks.
 *
 * The plan is plain arithmetic on (N, rank, V, P): tested for 1..64 ranks
 * without MPI (tests/test_unit_plan.c). */
#ifndef WS_UNIT_PLAN_H
#define WS_UNIT_PLAN_H
#include "nn/base/status.h"

/* Passes [begin, end) of one view; empty when begin >= end. */
typedef struct {
    int begin, end;
} ws_pass_range;

typedef struct {
    int ranks, rank;          /* N and this rank */
    int views;                /* V */
    long passes;              /* P, units per view */
    long lo, hi;              /* this rank's units [lo, hi) */
    int send_view;            /* the view whose part this rank sends to its owner; -1: none */
    int send_to;              /* that view's owner */
    ws_pass_range send;       /* the passes of send_view this rank computed */
    int recv_view;            /* the view this rank owns but did not finish; -1: none */
    ws_pass_range *recv;      /* ranks: the passes of recv_view each rank sends here */
} ws_unit_plan;

/* Allocates the plan of rank `rank` of `ranks`; ws_unit_plan_make fills it. */
int ws_unit_plan_init(ws_unit_plan *plan, int ranks, int rank, ws_status *st);
void ws_unit_plan_free(ws_unit_plan *plan);
/* The plan of a batch of `views` views of `passes` units each. */
void ws_unit_plan_make(ws_unit_plan *plan, int views, long passes);
/* The passes of view k (0..V-1) this rank computes. */
ws_pass_range ws_unit_plan_computes(const ws_unit_plan *plan, int k);
/* The rank that owns view k. */
int ws_unit_plan_owner(const ws_unit_plan *plan, int k);
/* Where this rank keeps the items of view k while it computes them: 0 for
 * the first view it touches, 1 for the others (each finished, or sent,
 * before the next), so that the part it sends and the view it receives
 * never share a buffer. */
int ws_unit_plan_slot(const ws_unit_plan *plan, int k);

#endif
