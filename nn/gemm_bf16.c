/* gemm_bf16.c: the bf16 products with frozen weights (gemm_bf16.h). */
#include <stdlib.h>
#include <string.h>
#include "gemm_bf16.h"
#include "parallel.h"

/* A panel: 4 vectors of 16 columns. A tile: 6 rows of a against one
 * panel, 24 accumulators of the 32 vector registers; per pair of k, 4
 * loads of B and 6 broadcasts of a feed 24 `vdpbf16ps`. */
enum { LANES = 16, PANEL_VECS = 4, PANEL = LANES * PANEL_VECS, TILE_ROWS = 6 };

/* Round to nearest even on the top 16 bits; a NaN keeps a set mantissa
 * bit (quiet) so that it cannot round to Inf. */
static uint16_t to_bf16(float x) {
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    if ((u & 0x7fffffffu) > 0x7f800000u) return (uint16_t)((u >> 16) | 0x40);
    return (uint16_t)((u + 0x7fffu + ((u >> 16) & 1u)) >> 16);
}

float nn_bf16_round(float x) {
    uint32_t u = (uint32_t)to_bf16(x) << 16;
    float y;
    memcpy(&y, &u, sizeof y);
    return y;
}

static int pairs(int k) { return (k + 1) / 2; }
static int vectors(int n) { return (n + LANES - 1) / LANES; }

int nn_bf16_matrix_pack(nn_bf16_matrix *p, const float *b, int k, int n, int trans_b, ws_status *st) {
    int kp = pairs(k), nv = vectors(n);
    size_t count = (size_t)kp * 2 * nv * LANES;
    p->k = k;
    p->n = n;
    p->data = ws_malloc(count * sizeof *p->data, "bf16 weights", st);
    if (!p->data) return st->code;
    /* each panel is written by one thread: the same bytes on any count */
#pragma omp parallel for schedule(static) if (nn_fork(count))
    for (int v0 = 0; v0 < nv; v0 += PANEL_VECS) {
        int pv = nv - v0 < PANEL_VECS ? nv - v0 : PANEL_VECS;
        uint16_t *panel = p->data + (size_t)v0 * LANES * 2 * kp;
        /* the inner loop runs along b's rows (i with trans_b, else c), so
         * that b is read in order; the panel (under 1 MB) takes the jumps */
        int rows = 2 * kp, cols = pv * LANES;
        for (int o = 0; o < (trans_b ? cols : rows); o++)
            for (int q = 0; q < (trans_b ? rows : cols); q++) {
                int i = trans_b ? q : o, c = trans_b ? o : q, j = v0 * LANES + c;
                float x = i < k && j < n ? (trans_b ? b[(size_t)j * k + i] : b[(size_t)i * n + j]) : 0.0f;
                panel[((size_t)(i / 2) * cols + c) * 2 + (i & 1)] = to_bf16(x);
            }
    }
    return WS_OK;
}

void nn_bf16_matrix_free(nn_bf16_matrix *p) {
    free(p->data);
    p->data = NULL;
}

int nn_bf16_linear_pack(nn_bf16_linear *l, const float *w, int N, int K, int w_kn, ws_status *st) {
    memset(l, 0, sizeof *l);
    if (nn_bf16_matrix_pack(&l->forward, w, K, N, !w_kn, st) ||
        nn_bf16_matrix_pack(&l->backward, w, N, K, w_kn, st)) {
        nn_bf16_linear_free(l);
        return st->code;
    }
    return WS_OK;
}

void nn_bf16_linear_free(nn_bf16_linear *l) {
    nn_bf16_matrix_free(&l->forward);
    nn_bf16_matrix_free(&l->backward);
}

size_t nn_bf16_gemm_work(int m, int k) { return (size_t)m * pairs(k); }

#if defined(__x86_64__)
#include <immintrin.h>

#define KERNEL __attribute__((target("avx512bf16,avx512f,avx512bw,avx512vl")))
#define INLINE_KERNEL KERNEL static inline __attribute__((always_inline))

int nn_bf16_available(void) {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512bf16") != 0;
}

/* Row i of a as bf16 pairs: a32[i * kp + q] holds columns 2q and 2q + 1
 * (an odd k's last pair ends in a zero). */
KERNEL static void round_rows(uint32_t *a32, const float *a, int i0, int i1, int k) {
    int kp = pairs(k);
    for (int i = i0; i < i1; i++) {
        const float *row = a + (size_t)i * k;
        uint16_t *out = (uint16_t *)(a32 + (size_t)i * kp);
        for (int j = 0; j < 2 * kp; j += 2 * LANES) {
            int lo = k - j < LANES ? k - j : LANES, hi = k - j - LANES;
            hi = hi < 0 ? 0 : hi > LANES ? LANES : hi;
            __m512 x0 = _mm512_maskz_loadu_ps((__mmask16)((1u << lo) - 1u), row + j);
            __m512 x1 = _mm512_maskz_loadu_ps((__mmask16)((1u << hi) - 1u), row + j + LANES);
            int left = 2 * kp - j < 2 * LANES ? 2 * kp - j : 2 * LANES;
            __mmask32 store = left == 2 * LANES ? 0xffffffffu : (__mmask32)((1u << left) - 1u);
            _mm512_mask_storeu_epi16(out + j, store, (__m512i)_mm512_cvtne2ps_pbh(x1, x0));
        }
    }
}

/* Columns of c this vector of the panel writes (the last may be short). */
static __mmask16 column_mask(int left) {
    return left >= LANES ? (__mmask16)0xffff : (__mmask16)((1u << left) - 1u);
}

/* rows x vecs of c from rows [i0, i0 + rows) of a32 and one panel; rows
 * and vecs are constants in every call (the switch below), so the
 * accumulators stay in registers. */
INLINE_KERNEL void tile(int rows, int vecs, float *c, const uint32_t *a32, const uint16_t *panel,
                        int kp, int n, int i0, int j0, const float *bias, const float *res, float beta) {
    __m512 acc[TILE_ROWS][PANEL_VECS];
#pragma GCC unroll 6
    for (int r = 0; r < rows; r++)
#pragma GCC unroll 4
        for (int v = 0; v < vecs; v++) acc[r][v] = _mm512_setzero_ps();
    const uint32_t *arow = a32 + (size_t)i0 * kp;
    for (int q = 0; q < kp; q++) {
        __m512bh bv[PANEL_VECS];
#pragma GCC unroll 4
        for (int v = 0; v < vecs; v++) bv[v] = (__m512bh)_mm512_loadu_si512(panel + ((size_t)q * vecs + v) * 2 * LANES);
#pragma GCC unroll 6
        for (int r = 0; r < rows; r++) {
            __m512bh av = (__m512bh)_mm512_set1_epi32((int)arow[(size_t)r * kp + q]);
#pragma GCC unroll 4
            for (int v = 0; v < vecs; v++) acc[r][v] = _mm512_dpbf16_ps(acc[r][v], av, bv[v]);
        }
    }
#pragma GCC unroll 6
    for (int r = 0; r < rows; r++) {
        size_t row = (size_t)(i0 + r) * n;
#pragma GCC unroll 4
        for (int v = 0; v < vecs; v++) {
            int j = j0 + v * LANES;
            __mmask16 mk = column_mask(n - j);
            __m512 init;
            if (bias || res) {
                __m512 b = bias ? _mm512_maskz_loadu_ps(mk, bias + j) : _mm512_setzero_ps();
                init = res ? _mm512_add_ps(_mm512_maskz_loadu_ps(mk, res + row + j), b) : b;
            } else {
                init = beta != 0.0f ? _mm512_maskz_loadu_ps(mk, c + row + j) : _mm512_setzero_ps();
            }
            _mm512_mask_storeu_ps(c + row + j, mk, _mm512_add_ps(init, acc[r][v]));
        }
    }
}

/* One panel (vecs vectors) against every row of a. */
KERNEL static void panel_rows(int vecs, float *c, const uint32_t *a32, const uint16_t *panel, int kp,
                              int m, int n, int j0, const float *bias, const float *res, float beta) {
#define TILE(R, V) tile(R, V, c, a32, panel, kp, n, i0, j0, bias, res, beta)
#define ROWS(V)                                                           \
    do {                                                                  \
        int i0 = 0;                                                       \
        for (; i0 + TILE_ROWS <= m; i0 += TILE_ROWS) TILE(TILE_ROWS, V);  \
        switch (m - i0) {                                                 \
        case 5: TILE(5, V); break;                                        \
        case 4: TILE(4, V); break;                                        \
        case 3: TILE(3, V); break;                                        \
        case 2: TILE(2, V); break;                                        \
        case 1: TILE(1, V); break;                                        \
        default: break;                                                   \
        }                                                                 \
    } while (0)
    switch (vecs) {
    case 4: ROWS(4); break;
    case 3: ROWS(3); break;
    case 2: ROWS(2); break;
    default: ROWS(1); break;
    }
#undef ROWS
#undef TILE
}

void nn_bf16_gemm(float *c, const float *a, const nn_bf16_matrix *b, int m, const float *bias,
                  const float *res, float beta, float *work) {
    int k = b->k, n = b->n, kp = pairs(k), nv = vectors(n);
    int panels = (nv + PANEL_VECS - 1) / PANEL_VECS;
    uint32_t *a32 = (uint32_t *)work;
    int fork = nn_fork((size_t)m * n * k);
#pragma omp parallel if (fork)
    {
        /* rounding a is elementwise: any split of the rows gives the same bits */
#pragma omp for schedule(static)
        for (int i = 0; i < m; i++) round_rows(a32, a, i, i + 1, k);
#pragma omp for schedule(static)
        for (int p = 0; p < panels; p++) {
            int v0 = p * PANEL_VECS, vecs = nv - v0 < PANEL_VECS ? nv - v0 : PANEL_VECS;
            const uint16_t *panel = b->data + (size_t)v0 * LANES * 2 * kp;
            panel_rows(vecs, c, a32, panel, kp, m, n, v0 * LANES, bias, res, beta);
        }
    }
}

#else

int nn_bf16_available(void) { return 0; }

void nn_bf16_gemm(float *c, const float *a, const nn_bf16_matrix *b, int m, const float *bias,
                  const float *res, float beta, float *work) {
    abort(); /* callers check nn_bf16_available first */
}

#endif
