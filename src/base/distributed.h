/* distributed.h: the ranks of an MPI job (`make MPI=1`, then `mpirun -np N
 * wiresketch fit ...`), behind the few collectives the fit needs.
 *
 * Built without MPI, or before ws_dist_init, there is one rank and the
 * collectives copy. Every rank calls the collectives in the same order. A
 * collective that fails (another rank has died) ends the whole job at once
 * with one line on stderr; files are written through a temporary name
 * (base/outfile.h), so the last checkpoint stays whole. */
#ifndef WS_DISTRIBUTED_H
#define WS_DISTRIBUTED_H
#include <stddef.h>
#include "nn/base/status.h"

/* Joins the job mpirun started (a no-op without MPI). */
int ws_dist_init(ws_status *st);
/* Leaves it (every rank, at the end). */
void ws_dist_finalize(void);
int ws_dist_rank(void);
int ws_dist_size(void);

/* All to all: send_bytes[r] bytes at send + send_off[r] go to rank r, and
 * recv_bytes[r] bytes from rank r land at recv + recv_off[r] (arrays of
 * ws_dist_size() entries; this rank's own entry must be 0). */
void ws_dist_exchange(const void *send, const size_t *send_bytes, const size_t *send_off, void *recv,
                      const size_t *recv_bytes, const size_t *recv_off);
/* Every rank's part of buf, bytes[r] bytes at offset bytes[0] + ... +
 * bytes[r - 1], is written by rank r beforehand; afterwards every rank
 * holds all of them. */
void ws_dist_allgather(void *buf, const size_t *bytes);
/* The largest of the ranks' values. */
int ws_dist_max(int value);

/* Where each rank may have failed on its own (a file one machine lacks):
 * every rank passes its code and status and gets the same code back, that
 * of rank 0 if it failed, else of the lowest rank that did. Only that rank
 * keeps its message (with "rank R: " in front when it is not rank 0), so
 * the job reports one line; the others' st->msg is left empty. */
int ws_dist_agree(int rc, ws_status *st);

/* Ends the whole job with exit status 1: "wiresketch: rank R: MSG" on
 * stderr. For an error one rank meets alone in the middle of a step, where
 * the others wait in a collective. */
_Noreturn void ws_dist_abort(const char *msg);

/* A failure this rank met alone while the others wait for it in a
 * collective: with several ranks, ws_dist_abort(st->msg); with one,
 * returns st->code. */
int ws_dist_fail_alone(const ws_status *st);

/* Bytes this rank has sent to other ranks so far: what each collective
 * hands to the others (an exchange's sends; an all-gather's or maximum's
 * part once per other rank), not what the network carries for it. */
size_t ws_dist_bytes_sent(void);

#endif
