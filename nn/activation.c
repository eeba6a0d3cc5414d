/* activation.c: quick_gelu (activation.h). The sigmoid is the stable
 * two-sided one of fastmath.h, so z = +-100 gives z and -0, and the
 * derivative 1 and 0, without overflow. */
#include "activation.h"
#include "fastmath.h"
#include "parallel.h"

#define QUICK_GELU_K 1.702f
/* Elements per OpenMP task: whole cache lines, few tasks. */
#define CHUNK 4096

NN_SIMD_CLONES static void forward_chunk(float *out, const float *z, size_t n) {
#pragma omp simd
    for (size_t i = 0; i < n; i++) {
        float s, sc;
        nn_sigmoid2(QUICK_GELU_K * z[i], &s, &sc);
        out[i] = z[i] * s;
    }
}

NN_SIMD_CLONES static void backward_chunk(float *dz, const float *dout, const float *z, size_t n,
                                          int acc) {
#pragma omp simd
    for (size_t i = 0; i < n; i++) {
        float s, sc;
        nn_sigmoid2(QUICK_GELU_K * z[i], &s, &sc);
        float d = dout[i] * (s + QUICK_GELU_K * z[i] * s * sc);
        dz[i] = (acc ? dz[i] : 0.0f) + d;
    }
}

static size_t chunk_len(size_t n, long c) {
    size_t start = (size_t)c * CHUNK;
    return n - start < CHUNK ? n - start : CHUNK;
}

void nn_quick_gelu_forward(float *out, const float *z, size_t n) {
    long chunks = (long)((n + CHUNK - 1) / CHUNK);
#pragma omp parallel for schedule(static) if (nn_fork(n))
    for (long c = 0; c < chunks; c++)
        forward_chunk(out + (size_t)c * CHUNK, z + (size_t)c * CHUNK, chunk_len(n, c));
}

void nn_quick_gelu_backward(float *dz, const float *dout, const float *z, size_t n, int acc) {
    long chunks = (long)((n + CHUNK - 1) / CHUNK);
#pragma omp parallel for schedule(static) if (nn_fork(n))
    for (long c = 0; c < chunks; c++) {
        size_t o = (size_t)c * CHUNK;
        backward_chunk(dz + o, dout + o, z + o, chunk_len(n, c), acc);
    }
}

static void forward(const nn_op *op) {
    nn_quick_gelu_forward(op->out->data, op->in[0]->data, op->out->numel);
}

static void backward(const nn_op *op) {
    nn_tensor *z = op->in[0];
    if (!z->grad) return;
    int acc = nn_grad_begin(z);
    nn_quick_gelu_backward(z->grad, op->out->grad, z->data, z->numel, acc);
}

nn_tensor *nn_quick_gelu(nn_tape *t, nn_tensor *z) {
    nn_op *op = nn_tape_append(t, NN_OP_QUICK_GELU, forward, backward);
    nn_tape_read(t, op, 0, z, 1);
    return nn_tape_output(t, op, z->ndim, z->shape);
}
