/* tape.c: recording, memory planning and replay of the op tape (tape.h). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "parallel.h"
#include "tape.h"

int nn_tape_init(nn_tape *t, int max_ops, int with_grad, ws_status *st) {
    memset(t, 0, sizeof *t);
    t->max_ops = max_ops;
    /* Every op makes at most an output, a saved tensor and two
     * workspaces; a few inputs. */
    t->max_tensors = 4 * max_ops + 8;
    t->with_grad = with_grad;
    /* One spare slot each: what an overflowing constructor writes into, so
     * that recording never fails midway; nn_tape_plan reports it. */
    t->ops = ws_calloc((size_t)max_ops + 1, sizeof *t->ops, "tape ops", st);
    t->tensors = ws_calloc((size_t)t->max_tensors + 1, sizeof *t->tensors, "tape tensors", st);
    if (!t->ops || !t->tensors) {
        nn_tape_free(t);
        return st->code;
    }
    return WS_OK;
}

void nn_tape_free(nn_tape *t) {
    free(t->ops);
    free(t->tensors);
    free(t->block);
    memset(t, 0, sizeof *t);
}

static nn_tensor *new_tensor(nn_tape *t, int ndim, const int *shape) {
    nn_tensor *x;
    if (t->ntensors < t->max_tensors) {
        x = &t->tensors[t->ntensors++];
    } else {
        t->overflow = 1;
        x = &t->tensors[t->max_tensors];
    }
    memset(x, 0, sizeof *x);
    x->ndim = ndim;
    x->numel = 1;
    for (int i = 0; i < ndim; i++) {
        x->shape[i] = shape[i];
        x->numel *= (size_t)shape[i];
    }
    x->producer = -1;
    x->last_read = -1;
    x->last_grad_use = -1;
    return x;
}

static int op_index(const nn_tape *t, const nn_op *op) { return (int)(op - t->ops); }

nn_tensor *nn_tape_input(nn_tape *t, int ndim, const int *shape) {
    nn_tensor *x = new_tensor(t, ndim, shape);
    x->external = 1;
    x->needs_grad = t->with_grad;
    return x;
}

void nn_tape_keep(nn_tape *t, nn_tensor *x) { x->keep = 1; }

const char *nn_op_kind_name(nn_op_kind kind) {
    static const char *const names[NN_OP_KINDS] = {
        [NN_OP_SEED] = "seed",           [NN_OP_NORMALISE] = "normalise",
        [NN_OP_PATCHIFY] = "patchify",   [NN_OP_TOKENS] = "tokens",
        [NN_OP_CLASS_TOKEN] = "class_token", [NN_OP_LAYERNORM] = "layernorm",
        [NN_OP_MATMUL] = "matmul",       [NN_OP_ATTENTION] = "attention",
        [NN_OP_QUICK_GELU] = "quick_gelu",
    };
    return kind >= 0 && kind < NN_OP_KINDS ? names[kind] : "?";
}

nn_op *nn_tape_append(nn_tape *t, nn_op_kind kind, nn_op_fn forward, nn_op_fn backward) {
    nn_op *op;
    if (t->nops < t->max_ops) {
        op = &t->ops[t->nops++];
    } else {
        t->overflow = 1;
        op = &t->ops[t->max_ops];
    }
    memset(op, 0, sizeof *op);
    op->kind = kind;
    op->forward = forward;
    op->backward = backward;
    return op;
}

void nn_tape_read(nn_tape *t, nn_op *op, int slot, nn_tensor *x, int needed_by_backward) {
    int i = op_index(t, op);
    op->in[slot] = x;
    if (i > x->last_read) x->last_read = i;
    if (x->needs_grad && i > x->last_grad_use) x->last_grad_use = i;
    if (needed_by_backward && t->with_grad) x->keep = 1;
}

nn_tensor *nn_tape_output(nn_tape *t, nn_op *op, int ndim, const int *shape) {
    nn_tensor *x = new_tensor(t, ndim, shape);
    x->producer = op_index(t, op);
    for (int k = 0; k < 2; k++)
        if (op->in[k] && op->in[k]->needs_grad) x->needs_grad = 1;
    op->out = x;
    return x;
}

/* A flat tensor that op writes and nobody else reads. */
static nn_tensor *op_private(nn_tape *t, nn_op *op, size_t numel) {
    int n = (int)numel;
    nn_tensor *x = new_tensor(t, 1, &n);
    x->numel = numel;
    x->producer = op_index(t, op);
    return x;
}

nn_tensor *nn_tape_saved(nn_tape *t, nn_op *op, size_t numel) {
    nn_tensor *x = op_private(t, op, numel);
    x->keep = t->with_grad;
    op->saved = x;
    return x;
}

nn_tensor *nn_tape_workspace(nn_tape *t, nn_op *op, size_t numel, int for_backward) {
    nn_tensor *x = op_private(t, op, numel);
    x->backward_work = for_backward;
    op->work[for_backward] = x;
    return x;
}

void nn_grad_add(nn_tensor *x, const float *g) {
    float *dx = x->grad;
    long n = (long)x->numel;
    int acc = nn_grad_begin(x);
    /* a residual's gradient (192k floats a block in CLIP): on the team,
     * not on one thread while the others wait */
#pragma omp parallel for simd schedule(static) if (nn_fork((size_t)n))
    for (long i = 0; i < n; i++) dx[i] = acc ? dx[i] + g[i] : g[i];
}

static void seed_backward(const nn_op *op) {
    const float *g = *op->seed;
    nn_tensor *x = op->in[0];
    if (g && x->grad) nn_grad_add(x, g);
}

void nn_tape_seed(nn_tape *t, nn_tensor *x, const float *const *slot) {
    nn_op *op = nn_tape_append(t, NN_OP_SEED, NULL, seed_backward);
    op->in[0] = x;
    op->seed = slot;
    int i = op_index(t, op);
    if (x->needs_grad && i > x->last_grad_use) x->last_grad_use = i;
}

/* ---- planning ----------------------------------------------------------
 * Each buffer lives over an interval of op indices: a value from the op
 * that writes it to the last op whose forward reads it; a gradient from
 * its producer (whose backward reads it last) to the last op whose
 * backward writes it. The overlap test is the same in both directions of
 * time, so one greedy first-fit (largest first) packs both kinds. */

enum { ALIGN_FLOATS = 16 }; /* 64 bytes */

typedef struct {
    int start, end;
    size_t size, offset;
    int id;
} interval;

static size_t round_up(size_t n) { return (n + ALIGN_FLOATS - 1) / ALIGN_FLOATS * ALIGN_FLOATS; }

static int by_size_desc(const void *a, const void *b) {
    const interval *x = a, *y = b;
    if (x->size != y->size) return x->size < y->size ? 1 : -1;
    return x->id - y->id;
}

static int by_offset(const void *a, const void *b) {
    const interval *x = *(interval *const *)a, *y = *(interval *const *)b;
    if (x->offset != y->offset) return x->offset < y->offset ? -1 : 1;
    return 0;
}

/* Assigns offsets so that intervals overlapping in time never overlap in
 * memory; returns the floats needed. `busy` has room for n pointers. */
static size_t first_fit(interval *v, int n, interval **busy) {
    qsort(v, (size_t)n, sizeof *v, by_size_desc);
    size_t peak = 0;
    for (int i = 0; i < n; i++) {
        int nb = 0;
        for (int j = 0; j < i; j++)
            if (v[j].start <= v[i].end && v[i].start <= v[j].end) busy[nb++] = &v[j];
        qsort(busy, (size_t)nb, sizeof *busy, by_offset);
        size_t off = 0;
        for (int j = 0; j < nb; j++) {
            if (off + v[i].size <= busy[j]->offset) break;
            if (busy[j]->offset + busy[j]->size > off) off = busy[j]->offset + busy[j]->size;
        }
        v[i].offset = off;
        if (off + v[i].size > peak) peak = off + v[i].size;
    }
    return peak;
}

static int max_int(int a, int b) { return a > b ? a : b; }

int nn_tape_plan(nn_tape *t, ws_status *st) {
    if (t->overflow)
        return ws_fail(st, WS_EINTERNAL, "tape: more than %d ops recorded", t->max_ops);
    int rc = WS_OK, n = t->ntensors;
    interval *scratch = ws_malloc((size_t)n * sizeof *scratch, "tape plan", st);
    interval *grads = ws_malloc((size_t)n * sizeof *grads, "tape plan", st);
    interval **busy = ws_malloc((size_t)n * sizeof *busy, "tape plan", st);
    size_t *keep_offset = ws_malloc((size_t)n * sizeof *keep_offset, "tape plan", st);
    if (!scratch || !grads || !busy || !keep_offset) {
        rc = st->code;
        goto done;
    }

    int ns = 0, ng = 0;
    size_t keep = 0;
    for (int i = 0; i < n; i++) {
        nn_tensor *x = &t->tensors[i];
        if (x->external) continue;
        size_t size = round_up(x->numel);
        if (x->backward_work) {
            if (t->with_grad) grads[ng++] = (interval){x->producer, x->producer, size, 0, i};
            continue;
        }
        if (x->keep) {
            keep_offset[i] = keep;
            keep += size;
        } else {
            scratch[ns++] = (interval){x->producer, max_int(x->producer, x->last_read), size, 0, i};
        }
        if (t->with_grad && x->needs_grad)
            grads[ng++] = (interval){x->producer, max_int(x->producer, x->last_grad_use), size, 0, i};
    }
    t->keep_floats = keep;
    t->scratch_floats = first_fit(scratch, ns, busy);
    t->grad_floats = first_fit(grads, ng, busy);

    size_t total = t->keep_floats + t->scratch_floats + t->grad_floats;
    free(t->block);
    t->block = ws_malloc(total * sizeof(float) + 64, "activation arena", st);
    if (!t->block) {
        rc = st->code;
        goto done;
    }
    float *base = (float *)(((uintptr_t)t->block + 63) & ~(uintptr_t)63);
    float *scratch_base = base + t->keep_floats, *grad_base = scratch_base + t->scratch_floats;
    for (int i = 0; i < n; i++)
        if (t->tensors[i].keep && !t->tensors[i].external) t->tensors[i].data = base + keep_offset[i];
    for (int k = 0; k < ns; k++) t->tensors[scratch[k].id].data = scratch_base + scratch[k].offset;
    for (int k = 0; k < ng; k++) {
        nn_tensor *x = &t->tensors[grads[k].id];
        *(x->backward_work ? &x->data : &x->grad) = grad_base + grads[k].offset;
    }
done:
    free(scratch);
    free(grads);
    free(busy);
    free(keep_offset);
    return rc;
}

void nn_tape_profile(nn_tape *t, double *seconds) { t->op_seconds = seconds; }

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Runs fn(op), timed into op_seconds[slot] when profiling. */
static void run_op(const nn_tape *t, nn_op_fn fn, const nn_op *op, int slot) {
    if (!t->op_seconds) {
        fn(op);
        return;
    }
    double t0 = now();
    fn(op);
    t->op_seconds[slot] = now() - t0;
}

void nn_tape_forward(nn_tape *t) {
    if (t->op_seconds) memset(t->op_seconds, 0, (size_t)t->nops * sizeof *t->op_seconds);
    for (int i = 0; i < t->nops; i++)
        if (t->ops[i].forward) run_op(t, t->ops[i].forward, &t->ops[i], i);
}

void nn_tape_backward(nn_tape *t) {
    for (int i = 0; i < t->ntensors; i++) t->tensors[i].grad_ready = 0;
    if (t->op_seconds) memset(t->op_seconds + t->nops, 0, (size_t)t->nops * sizeof *t->op_seconds);
    for (int i = t->nops - 1; i >= 0; i--) {
        const nn_op *op = &t->ops[i];
        int reached = !op->out || (op->out->grad && op->out->grad_ready) || (op->seed && *op->seed);
        if (!reached) continue;
        run_op(t, op->backward, op, t->nops + i);
    }
}

size_t nn_tape_bytes(const nn_tape *t) {
    return (t->keep_floats + t->scratch_floats + t->grad_floats) * sizeof(float);
}
