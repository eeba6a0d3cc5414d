/* normalise.c: per-channel normalisation (normalise.h). */
#include "normalise.h"

void nn_normalise_forward(float *out, const float *img, const float *mean, const float *std, int B,
                          int C, int HW) {
    for (int b = 0; b < B; b++)
        for (int c = 0; c < C; c++) {
            size_t o = ((size_t)b * C + c) * HW;
            float m = mean[c], s = std[c];
#pragma omp simd
            for (int i = 0; i < HW; i++) out[o + i] = (img[o + i] - m) / s;
        }
}

void nn_normalise_backward(float *d_img, const float *d_out, const float *std, int B, int C, int HW,
                           int acc) {
    for (int b = 0; b < B; b++)
        for (int c = 0; c < C; c++) {
            size_t o = ((size_t)b * C + c) * HW;
            float s = std[c];
#pragma omp simd
            for (int i = 0; i < HW; i++) d_img[o + i] = (acc ? d_img[o + i] : 0.0f) + d_out[o + i] / s;
        }
}

/* n[0] = B, n[1] = C, n[2] = HW; w[0] mean, w[1] std. */
static void forward(const nn_op *op) {
    nn_normalise_forward(op->out->data, op->in[0]->data, op->w[0], op->w[1], op->n[0], op->n[1],
                         op->n[2]);
}

static void backward(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    nn_normalise_backward(x->grad, op->out->grad, op->w[1], op->n[0], op->n[1], op->n[2], acc);
}

nn_tensor *nn_normalise(nn_tape *t, nn_tensor *img, const float *mean, const float *std) {
    nn_op *op = nn_tape_append(t, NN_OP_NORMALISE, forward, backward);
    nn_tape_read(t, op, 0, img, 0);
    op->w[0] = mean;
    op->w[1] = std;
    op->n[0] = img->shape[0];
    op->n[1] = img->shape[1];
    op->n[2] = (int)(img->numel / ((size_t)op->n[0] * op->n[1]));
    return nn_tape_output(t, op, img->ndim, img->shape);
}
