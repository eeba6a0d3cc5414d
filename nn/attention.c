/* attention.c: multi-head self-attention (attention.h).
 *
 * Each (image, head) pair is an independent OpenMP task with its own
 * scratch, and writes only its own columns of out / dqkv: no reduction
 * across threads, the same bits on every run. A head is too small for a
 * GEMM call to pay (T x T x D = 50 x 50 x 64), so every product is one
 * tight kernel, combine(), on copies of q, k, v padded to whole vector
 * blocks (and transposed where the sum runs over D). */
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "attention.h"
#include "fastmath.h"
#include "parallel.h"

/* combine() works on blocks of up to 4 output rows x 32 floats, each row
 * held as two 16-float vectors (GCC vector extension) in named variables,
 * so that the compiler keeps the block in registers (8 AVX-512 or 16 AVX2
 * registers depending on the clone). Every x loaded serves 4 rows, so the
 * kernel runs at the speed of the multiply-adds, not of the loads. */
enum { LANES = 32, VEC = 16, ROWS = 4 };
typedef float vec16 __attribute__((vector_size(VEC * sizeof(float)), aligned(sizeof(float))));

static int round_lanes(int n) { return (n + LANES - 1) / LANES * LANES; }

/* Vectors go through pointers and memcpy, never by value: a helper that
 * takes or returns a vector changes the ABI between the clones. */
NN_INLINE void load16(vec16 *v, const float *p) { memcpy(v, p, sizeof *v); }

/* y[0..m) = (acc ? y : 0) + the row's sums (lo, hi), m <= LANES. */
NN_INLINE void store_row(float *y, int acc, const vec16 *lo, const vec16 *hi, int m) {
    if (m == LANES) {
        vec16 y0 = {0}, y1 = {0};
        if (acc) {
            load16(&y0, y);
            load16(&y1, y + VEC);
        }
        y0 += *lo;
        y1 += *hi;
        memcpy(y, &y0, sizeof y0);
        memcpy(y + VEC, &y1, sizeof y1);
        return;
    }
    float sums[LANES];
    memcpy(sums, lo, sizeof *lo);
    memcpy(sums + VEC, hi, sizeof *hi);
    for (int l = 0; l < m; l++) y[l] = (acc ? y[l] : 0.0f) + sums[l];
}

/* Rows r < rows (4, or 1 for the remainder) of combine(), lanes [0, m) of
 * y and x (x readable up to LANES). */
NN_INLINE void combine_block(float *y, size_t ys, int acc, const float *c, size_t crs, size_t cs,
                             const float *x, size_t xs, int n, int rows, int m) {
    vec16 a0 = {0}, a1 = {0}, b0 = {0}, b1 = {0}, c0 = {0}, c1 = {0}, d0 = {0}, d1 = {0};
    for (int k = 0; k < n; k++) {
        vec16 x0, x1;
        load16(&x0, x + k * xs);
        load16(&x1, x + k * xs + VEC);
        const float *ck = c + k * cs;
        a0 += ck[0] * x0;
        a1 += ck[0] * x1;
        if (rows == ROWS) {
            b0 += ck[crs] * x0;
            b1 += ck[crs] * x1;
            c0 += ck[2 * crs] * x0;
            c1 += ck[2 * crs] * x1;
            d0 += ck[3 * crs] * x0;
            d1 += ck[3 * crs] * x1;
        }
    }
    store_row(y, acc, &a0, &a1, m);
    if (rows == ROWS) {
        store_row(y + ys, acc, &b0, &b1, m);
        store_row(y + 2 * ys, acc, &c0, &c1, m);
        store_row(y + 3 * ys, acc, &d0, &d1, m);
    }
}

/* y[r*ys + l] = (acc ? y[r*ys + l] : 0) + sum_{k<n} c[r*crs + k*cs] x[k*xs + l]
 * for r < R, l < L. Rows of x must be readable up to L rounded up to
 * LANES. Each sum runs over k in order, in one vector lane: the same bits
 * whatever R, and no sum across lanes. */
NN_INLINE void combine(float *y, size_t ys, int acc, const float *c, size_t crs, size_t cs,
                       const float *x, size_t xs, int n, int R, int L) {
    for (int l0 = 0; l0 < L; l0 += LANES) {
        int m = L - l0 < LANES ? L - l0 : LANES;
        int r = 0;
        for (; r + ROWS <= R; r += ROWS)
            combine_block(y + r * ys + l0, ys, acc, c + r * crs, crs, cs, x + l0, xs, n, ROWS, m);
        for (; r < R; r++)
            combine_block(y + r * ys + l0, ys, acc, c + r * crs, crs, cs, x + l0, xs, n, 1, m);
    }
}

/* dst [T][Dp] = the T rows of D floats at src (row apart), zero padded. */
NN_INLINE void gather_rows(float *dst, const float *src, size_t row, int T, int D, int Dp) {
    for (int j = 0; j < T; j++) {
        memcpy(dst + (size_t)j * Dp, src + j * row, (size_t)D * sizeof *dst);
        memset(dst + (size_t)j * Dp + D, 0, (size_t)(Dp - D) * sizeof *dst);
    }
}

/* A 16 x 16 transpose in four steps h = 8, 4, 2, 1: rows i and i + h
 * exchange their off-diagonal h x h blocks. Lane l of step h's masks
 * picks from the pair (a, b) = (row i, row i + h), b's lanes numbered
 * from 16; each shuffle is one vpermt2ps under AVX-512. */
typedef int32_t ivec16 __attribute__((vector_size(VEC * sizeof(int32_t))));
static const ivec16 swap_lo[4] = {
    {0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23},
    {0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27},
    {0, 1, 16, 17, 4, 5, 20, 21, 8, 9, 24, 25, 12, 13, 28, 29},
    {0, 16, 2, 18, 4, 20, 6, 22, 8, 24, 10, 26, 12, 28, 14, 30}};
static const ivec16 swap_hi[4] = {
    {8, 9, 10, 11, 12, 13, 14, 15, 24, 25, 26, 27, 28, 29, 30, 31},
    {4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31},
    {2, 3, 18, 19, 6, 7, 22, 23, 10, 11, 26, 27, 14, 15, 30, 31},
    {1, 17, 3, 19, 5, 21, 7, 23, 9, 25, 11, 27, 13, 29, 15, 31}};

/* dst (rows ds apart) = the 16 x 16 tile at src (rows ss apart) transposed. */
NN_INLINE void transpose_tile(float *dst, size_t ds, const float *src, size_t ss) {
    vec16 r[VEC];
    for (int i = 0; i < VEC; i++) memcpy(&r[i], src + i * ss, sizeof r[i]);
#pragma GCC unroll 4
    for (int step = 0; step < 4; step++) {
        int h = 8 >> step;
#pragma GCC unroll 16
        for (int i = 0; i < VEC; i++)
            if (!(i & h)) {
                vec16 a = r[i], b = r[i + h];
                r[i] = __builtin_shuffle(a, b, swap_lo[step]);
                r[i + h] = __builtin_shuffle(a, b, swap_hi[step]);
            }
    }
    for (int i = 0; i < VEC; i++) memcpy(dst + i * ds, &r[i], sizeof r[i]);
}

/* dst [D][Tp] = the same rows transposed, zero padded: whole 16 x 16
 * tiles by shuffles, the rest element by element. */
NN_INLINE void gather_transposed(float *dst, const float *src, size_t row, int T, int D, int Tp) {
    for (int d = 0; d < D; d++) memset(dst + (size_t)d * Tp + T, 0, (size_t)(Tp - T) * sizeof *dst);
    int Tt = T / VEC * VEC, Dt = D / VEC * VEC;
    for (int j = 0; j < Tt; j += VEC)
        for (int d = 0; d < Dt; d += VEC)
            transpose_tile(dst + (size_t)d * Tp + j, (size_t)Tp, src + j * row + d, row);
    for (int j = 0; j < T; j++)
        for (int d = j < Tt ? Dt : 0; d < D; d++) dst[(size_t)d * Tp + j] = src[j * row + d];
}

/* Logits (unscaled) -> probabilities of scale * logits, in place. */
NN_INLINE void softmax_row(float *p, int n, float scale) {
    float mx = p[0];
#pragma omp simd reduction(max : mx)
    for (int j = 1; j < n; j++) mx = p[j] > mx ? p[j] : mx;
    float sum = 0.0f;
#pragma omp simd reduction(+ : sum)
    for (int j = 0; j < n; j++) {
        p[j] = nn_exp_nonpos(scale * (p[j] - mx));
        sum += p[j];
    }
    float inv = 1.0f / sum; /* sum >= 1: the maximum contributes exp(0) */
#pragma omp simd
    for (int j = 0; j < n; j++) p[j] *= inv;
}

static size_t head_forward_work(int T, int D) {
    return (size_t)D * round_lanes(T) + (size_t)T * round_lanes(D);
}

static size_t head_backward_work(int T, int D) {
    return (size_t)D * round_lanes(T) + 3 * (size_t)T * round_lanes(D) + (size_t)T * T;
}

size_t nn_attention_forward_work(int B, int T, int C, int H) {
    return (size_t)B * H * head_forward_work(T, C / H);
}

size_t nn_attention_backward_work(int B, int T, int C, int H) {
    return (size_t)B * H * head_backward_work(T, C / H);
}

/* One (image, head): q, k, v rows `row` floats apart, out rows out_row
 * apart; probs is the head's T x T block. */
NN_SIMD_CLONES static void head_forward(float *out, size_t out_row, float *probs, float *work,
                                        const float *q, const float *k, const float *v, size_t row,
                                        int T, int D) {
    int Tp = round_lanes(T), Dp = round_lanes(D);
    float *kt = work, *vp = work + (size_t)D * Tp;
    gather_transposed(kt, k, row, T, D, Tp);
    gather_rows(vp, v, row, T, D, Dp);
    float scale = 1.0f / sqrtf((float)D);
    combine(probs, (size_t)T, 0, q, row, 1, kt, (size_t)Tp, D, T, T); /* q_i . k_j */
    for (int i = 0; i < T; i++) softmax_row(probs + (size_t)i * T, T, scale);
    combine(out, out_row, 0, probs, (size_t)T, 1, vp, (size_t)Dp, T, T, D); /* sum_j p_ij v_j */
}

void nn_attention_forward(float *out, float *probs, float *work, const float *qkv, int B, int T,
                          int C, int H) {
    int D = C / H;
    size_t row = 3 * (size_t)C;
#pragma omp parallel for collapse(2) schedule(static) if (nn_fork((size_t)B * T * T * C))
    for (int b = 0; b < B; b++)
        for (int h = 0; h < H; h++) {
            const float *q = qkv + (size_t)b * T * row + (size_t)h * D;
            size_t bh = (size_t)b * H + h;
            head_forward(out + (size_t)b * T * C + (size_t)h * D, (size_t)C, probs + bh * T * T,
                         work + bh * head_forward_work(T, D), q, q + C, q + 2 * C, row, T, D);
        }
}

/* One (image, head) of the backward. With s_ij = scale q_i.k_j,
 * p = softmax(s), out_i = sum_j p_ij v_j, g_i = dL/dout_i and G_ij the
 * gradient arriving on p_ij itself (dprobs):
 *   dp_ij = g_i.v_j + G_ij,  ds_ij = scale p_ij (dp_ij - sum_k p_ik dp_ik),
 *   dq_i = sum_j ds_ij k_j,  dk_j = sum_i ds_ij q_i,  dv_j = sum_i p_ij g_i.
 * g or G may be NULL (none arrived): g NULL makes dv zero. */
NN_SIMD_CLONES static void head_backward(float *dq, float *dk, float *dv, int acc, const float *g,
                                         size_t out_row, const float *dprobs, const float *probs,
                                         float *work, const float *q, const float *k,
                                         const float *v, size_t row, int T, int D) {
    int Tp = round_lanes(T), Dp = round_lanes(D);
    float *vt = work, *kp = vt + (size_t)D * Tp, *qp = kp + (size_t)T * Dp;
    float *gp = qp + (size_t)T * Dp, *ds = gp + (size_t)T * Dp;
    gather_rows(kp, k, row, T, D, Dp);
    gather_rows(qp, q, row, T, D, Dp);
    if (g) {
        gather_transposed(vt, v, row, T, D, Tp);
        gather_rows(gp, g, out_row, T, D, Dp);
        combine(ds, (size_t)T, 0, gp, (size_t)Dp, 1, vt, (size_t)Tp, D, T, T); /* g_i.v_j */
    } else {
        memset(ds, 0, (size_t)T * T * sizeof *ds);
    }
    if (dprobs)
        for (size_t i = 0; i < (size_t)T * T; i++) ds[i] += dprobs[i];
    float scale = 1.0f / sqrtf((float)D);
    for (int i = 0; i < T; i++) {
        const float *p = probs + (size_t)i * T;
        float *dsi = ds + (size_t)i * T;
        float pdp = 0.0f;
#pragma omp simd reduction(+ : pdp)
        for (int j = 0; j < T; j++) pdp += p[j] * dsi[j];
#pragma omp simd
        for (int j = 0; j < T; j++) dsi[j] = scale * p[j] * (dsi[j] - pdp);
    }
    combine(dq, row, acc, ds, (size_t)T, 1, kp, (size_t)Dp, T, T, D);
    combine(dk, row, acc, ds, 1, (size_t)T, qp, (size_t)Dp, T, T, D);
    if (g)
        combine(dv, row, acc, probs, 1, (size_t)T, gp, (size_t)Dp, T, T, D);
    else if (!acc)
        for (int j = 0; j < T; j++) memset(dv + j * row, 0, (size_t)D * sizeof *dv);
}

void nn_attention_backward(float *dqkv, const float *dout, const float *dprobs, const float *qkv,
                           const float *probs, float *work, int B, int T, int C, int H, int acc) {
    int D = C / H;
    size_t row = 3 * (size_t)C;
#pragma omp parallel for collapse(2) schedule(static) if (nn_fork((size_t)B * T * T * C))
    for (int b = 0; b < B; b++)
        for (int h = 0; h < H; h++) {
            size_t base = (size_t)b * T * row + (size_t)h * D, bh = (size_t)b * H + h;
            float *dq = dqkv + base;
            const float *q = qkv + base;
            head_backward(dq, dq + C, dq + 2 * C, acc,
                          dout ? dout + (size_t)b * T * C + (size_t)h * D : NULL, (size_t)C,
                          dprobs ? dprobs + bh * T * T : NULL, probs + bh * T * T,
                          work + bh * head_backward_work(T, D), q, q + C, q + 2 * C, row, T, D);
        }
}

/* n[0] = B, n[1] = T, n[2] = C, n[3] = H; saved: probs [B,H,T,T]. */
static void forward(const nn_op *op) {
    nn_attention_forward(op->out->data, op->saved->data, op->work[0]->data, op->in[0]->data,
                         op->n[0], op->n[1], op->n[2], op->n[3]);
}

/* Runs when the output's gradient arrived or a gradient on the
 * probabilities was handed in (op->seed, nn_attention_probs). */
static void backward(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    const float *dout = op->out->grad && op->out->grad_ready ? op->out->grad : NULL;
    const float *dprobs = op->seed ? *op->seed : NULL;
    int acc = nn_grad_begin(x);
    nn_attention_backward(x->grad, dout, dprobs, x->data, op->saved->data, op->work[1]->data,
                          op->n[0], op->n[1], op->n[2], op->n[3], acc);
}

nn_tensor *nn_attention(nn_tape *t, nn_tensor *qkv, int heads) {
    nn_op *op = nn_tape_append(t, NN_OP_ATTENTION, forward, backward);
    nn_tape_read(t, op, 0, qkv, 1);
    int T = nn_dim(qkv, 1), C = nn_dim(qkv, 0) / 3, B = nn_rows(qkv) / T;
    op->n[0] = B;
    op->n[1] = T;
    op->n[2] = C;
    op->n[3] = heads;
    nn_tape_saved(t, op, (size_t)B * heads * T * T);
    nn_tape_workspace(t, op, nn_attention_forward_work(B, T, C, heads), 0);
    nn_tape_workspace(t, op, nn_attention_backward_work(B, T, C, heads), 1);
    int shape[3] = {B, T, C};
    return nn_tape_output(t, op, 3, shape);
}

nn_tensor *nn_attention_probs(nn_tape *t, nn_tensor *out, const float *const *dprobs) {
    nn_op *op = &t->ops[out->producer];
    nn_tape_keep(t, op->saved);
    op->seed = dprobs;
    return op->saved;
}
