/* tape.h: the op tape of the autograd engine (reverse mode, llm.c style).
 *
 * The graph is static: a model records its ops once (each op a pair of
 * forward/backward functions plus the tensors and frozen parameters they
 * use), the planner then lays every tensor and gradient out in ONE arena
 * allocated up front, and every step replays the tape forward and then in
 * reverse. Nothing is allocated during a step.
 *
 * Gradients exist only where some graph input wants one (the input image);
 * parameters are plain constant arrays and never receive a gradient. */
#ifndef NN_TAPE_H
#define NN_TAPE_H
#include "base/status.h"
#include "tensor.h"

typedef struct nn_op nn_op;
typedef void (*nn_op_fn)(const nn_op *op);

/* What an op computes: tools that walk a tape (benchmarks, profiles) ask
 * this, never the op's functions. */
typedef enum {
    NN_OP_SEED,
    NN_OP_NORMALISE,
    NN_OP_PATCHIFY,
    NN_OP_TOKENS,
    NN_OP_CLASS_TOKEN,
    NN_OP_LAYERNORM,
    NN_OP_MATMUL,
    NN_OP_ATTENTION,
    NN_OP_QUICK_GELU,
    NN_OP_KINDS
} nn_op_kind;

/* "matmul", "layernorm", ... */
const char *nn_op_kind_name(nn_op_kind kind);

struct nn_op {
    nn_op_kind kind;
    nn_op_fn forward;          /* NULL for a seed op (backward only) */
    nn_op_fn backward;
    nn_tensor *out;            /* NULL for a seed op */
    nn_tensor *in[2];          /* activations read */
    nn_tensor *saved;          /* state the forward leaves for the backward */
    nn_tensor *work[2];        /* scratch while the forward [0] / backward [1] runs */
    const float *w[2];         /* frozen parameters (weight, bias) */
    /* a matmul's weight packed for the bf16 kernel (gemm_bf16.h), or NULL:
     * the op then runs in fp32 */
    const struct nn_bf16_linear *w_bf16;
    int n[4];                  /* op-specific sizes, documented by each op */
    /* Slot holding an external gradient: a seed op's, or one an op takes
     * on its saved state (attention's probabilities); an op with a slot
     * holding a pointer runs its backward even when its output got none. */
    const float *const *seed;
};

typedef struct {
    nn_tensor *tensors;
    int ntensors, max_tensors;
    nn_op *ops;
    int nops, max_ops;
    int with_grad;             /* plan gradients and keep what backward reads */
    int overflow;              /* more ops than max_ops were recorded */
    void *block;               /* the one allocation */
    size_t keep_floats, scratch_floats, grad_floats;
    /* NULL, or 2 * nops seconds that each replay fills (nn_tape_profile). */
    double *op_seconds;
} nn_tape;

int nn_tape_init(nn_tape *t, int max_ops, int with_grad, ws_status *st);
void nn_tape_free(nn_tape *t);

/* A graph input whose data (and gradient, when with_grad) the caller sets
 * before each forward (and backward). */
nn_tensor *nn_tape_input(nn_tape *t, int ndim, const int *shape);
/* The caller reads x after the forward: its storage is never reused. */
void nn_tape_keep(nn_tape *t, nn_tensor *x);
/* Records a seed: during backward, *slot (when not NULL) is added to x's
 * gradient at this point of the tape; x's gradient then flows on. */
void nn_tape_seed(nn_tape *t, nn_tensor *x, const float *const *slot);

/* For op constructors: appends an op, declares what it reads, and creates
 * its output (and saved state). needed_by_backward: the op's backward
 * reads x's values, so they must survive until then. */
nn_op *nn_tape_append(nn_tape *t, nn_op_kind kind, nn_op_fn forward, nn_op_fn backward);
void nn_tape_read(nn_tape *t, nn_op *op, int slot, nn_tensor *x, int needed_by_backward);
nn_tensor *nn_tape_output(nn_tape *t, nn_op *op, int ndim, const int *shape);
nn_tensor *nn_tape_saved(nn_tape *t, nn_op *op, size_t numel);
/* Scratch the op uses while its forward (for_backward 0) or its backward
 * (1) runs, in op->work[for_backward]; it shares memory with whatever is
 * not alive at that moment. */
nn_tensor *nn_tape_workspace(nn_tape *t, nn_op *op, size_t numel, int for_backward);

/* For op backwards: adds g (x->numel floats) to x's gradient, or copies
 * it there when it is the first write (nn_grad_begin). */
void nn_grad_add(nn_tensor *x, const float *g);

/* Lays out every tensor and gradient and allocates the arena; after this
 * the tape can run. Fails on OOM or when max_ops was exceeded. */
int nn_tape_plan(nn_tape *t, ws_status *st);
void nn_tape_forward(nn_tape *t);
/* Replays the tape in reverse from the seeds (and the ops' own slots);
 * ops no gradient reaches are skipped. A graph input whose gradient never
 * arrived keeps grad_ready 0. */
void nn_tape_backward(nn_tape *t);
/* From now on every replay writes the time of op i's forward to
 * seconds[i] and of its backward to seconds[nops + i] (0 when it did not
 * run); seconds has 2 * nops entries, or is NULL to stop. For profiles:
 * it reads the clock twice per op. */
void nn_tape_profile(nn_tape *t, double *seconds);
/* Bytes of the arena. */
size_t nn_tape_bytes(const nn_tape *t);

#endif
