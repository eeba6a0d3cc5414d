/* tensor.h: the activations of the autograd engine.
 *
 * A tensor is a view into the tape's one arena (tape.h): its values and,
 * when a gradient flows through it, a gradient buffer of the same shape.
 * Storage is assigned by the tape's planner once the whole graph is known,
 * so a tensor only says how big it is and who reads it; the planner lets
 * tensors whose lifetimes do not overlap share memory. */
#ifndef NN_TENSOR_H
#define NN_TENSOR_H
#include <stddef.h>

enum { NN_MAX_DIMS = 4 };

typedef struct {
    float *data;
    float *grad;       /* NULL when no gradient flows through this tensor */
    int ndim;
    int shape[NN_MAX_DIMS];
    size_t numel;
    /* Backward bookkeeping: grad holds a value. A gradient that never
     * arrived is zero, so an op whose output gradient is not ready is
     * skipped, and the first op to write an input's gradient overwrites
     * instead of accumulating: no buffer is ever cleared. */
    int grad_ready;
    /* Planner bookkeeping (tape.c). */
    int producer;      /* index of the op that writes data; -1: external */
    int last_read;     /* last op whose forward reads data */
    int last_grad_use; /* last op whose backward writes grad (seeds count) */
    int keep;          /* data read after its last forward use (backward, caller) */
    int needs_grad;    /* a gradient flows here: some input of the graph wants one */
    int external;      /* data (and grad) are supplied by the caller */
    int backward_work; /* data is scratch of its op's backward (gradient region) */
} nn_tensor;

/* Size of dimension i counted from the end (nn_dim(t, 0) is the last). */
static inline int nn_dim(const nn_tensor *t, int from_end) { return t->shape[t->ndim - 1 - from_end]; }

/* Number of rows when the last dimension is the row: numel / last dim. */
static inline int nn_rows(const nn_tensor *t) { return (int)(t->numel / (size_t)nn_dim(t, 0)); }

/* Marks the start of an op's gradient write to t: returns 1 when the op
 * must accumulate into t->grad (another op already wrote it), 0 when it
 * must overwrite. */
static inline int nn_grad_begin(nn_tensor *t) {
    int acc = t->grad_ready;
    t->grad_ready = 1;
    return acc;
}

#endif
