/* distributed.c: the ranks of an MPI job (see distributed.h). WS_MPI (set by
 * `make MPI=1`) selects Open MPI; otherwise one rank, and the collectives
 * copy this rank's own part. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/distributed.h"
#ifdef WS_MPI
#include <mpi.h>
#endif

static int rank_, size_ = 1;
static size_t sent_;

int ws_dist_rank(void) { return rank_; }
int ws_dist_size(void) { return size_; }
size_t ws_dist_bytes_sent(void) { return sent_; }

_Noreturn void ws_dist_abort(const char *msg) {
    fprintf(stderr, "wiresketch: rank %d: %s\n", rank_, msg);
    fflush(stderr);
#ifdef WS_MPI
    if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, 1);
#endif
    exit(1);
}

int ws_dist_fail_alone(const ws_status *st) {
    if (size_ > 1) ws_dist_abort(st->msg);
    return st->code;
}

int ws_dist_agree(int rc, ws_status *st) {
    if (size_ == 1) return rc;
    int *codes = calloc((size_t)size_, sizeof(int));
    size_t *bytes = malloc((size_t)size_ * sizeof(size_t));
    if (!codes || !bytes) ws_dist_abort("out of memory for an exchange between ranks");
    codes[rank_] = rc;
    for (int r = 0; r < size_; r++) bytes[r] = sizeof(int);
    ws_dist_allgather(codes, bytes);
    int reporter = -1;
    for (int r = 0; r < size_ && reporter < 0; r++)
        if (codes[r]) reporter = r;
    int code = reporter < 0 ? WS_OK : codes[reporter];
    free(codes);
    free(bytes);
    if (reporter != rank_) {
        st->code = code;
        st->msg[0] = 0;
    } else if (rank_ > 0) {
        char msg[sizeof st->msg];
        snprintf(msg, sizeof msg, "%s", st->msg);
        ws_fail(st, code, "rank %d: %s", rank_, msg);
    }
    return code;
}

#ifdef WS_MPI
int ws_dist_init(ws_status *st) {
    int provided;
    /* OpenMP and OpenBLAS threads compute; only the main thread calls MPI. */
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return ws_fail(st, WS_EINPUT, "MPI: the job could not be joined (MPI_Init_thread failed)");
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    return WS_OK;
}

void ws_dist_finalize(void) { MPI_Finalize(); }

/* A failed collective: a peer is gone; nothing sensible is left to do. */
static void check(int rc, const char *what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING + 200], why[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, why, &len);
    snprintf(text, sizeof text, "%s failed (%s): another rank has stopped; the job ends", what, why);
    ws_dist_abort(text);
}

/* MPI counts are ints: a message over INT_MAX bytes is a bug here. */
static int to_int(size_t n) {
    if (n > INT_MAX) ws_dist_abort("a message of more than 2 GiB between ranks");
    return (int)n;
}

void ws_dist_exchange(const void *send, const size_t *send_bytes, const size_t *send_off, void *recv,
                      const size_t *recv_bytes, const size_t *recv_off) {
    int *counts = malloc(4 * (size_t)size_ * sizeof(int));
    if (!counts) ws_dist_abort("out of memory for an exchange between ranks");
    int *sc = counts, *sd = counts + size_, *rc = counts + 2 * size_, *rd = counts + 3 * size_;
    for (int r = 0; r < size_; r++) {
        sc[r] = to_int(send_bytes[r]);
        sd[r] = to_int(send_off[r]);
        rc[r] = to_int(recv_bytes[r]);
        rd[r] = to_int(recv_off[r]);
        sent_ += send_bytes[r];
    }
    check(MPI_Alltoallv(send, sc, sd, MPI_BYTE, recv, rc, rd, MPI_BYTE, MPI_COMM_WORLD), "MPI_Alltoallv");
    free(counts);
}

void ws_dist_allgather(void *buf, const size_t *bytes) {
    int *counts = malloc(2 * (size_t)size_ * sizeof(int));
    if (!counts) ws_dist_abort("out of memory for an exchange between ranks");
    size_t off = 0;
    for (int r = 0; r < size_; r++) {
        counts[r] = to_int(bytes[r]);
        counts[size_ + r] = to_int(off);
        off += bytes[r];
    }
    sent_ += bytes[rank_] * (size_t)(size_ - 1);
    check(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_BYTE, buf, counts, counts + size_, MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    free(counts);
}

int ws_dist_max(int value) {
    int out = value;
    sent_ += sizeof value * (size_t)(size_ - 1);
    check(MPI_Allreduce(&value, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
}
#else
int ws_dist_init(ws_status *st) { return WS_OK; }

void ws_dist_finalize(void) {}

void ws_dist_exchange(const void *send, const size_t *send_bytes, const size_t *send_off, void *recv,
                      const size_t *recv_bytes, const size_t *recv_off) {}

void ws_dist_allgather(void *buf, const size_t *bytes) {}

int ws_dist_max(int value) { return value; }
#endif
