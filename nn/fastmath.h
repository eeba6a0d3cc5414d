/* fastmath.h: exp and sigmoid in a form the compiler vectorises.
 *
 * glibc's expf is a function call per element, which keeps the loops of
 * quick_gelu and softmax scalar; these inline versions have no branches,
 * so a `#pragma omp simd` loop runs them several lanes wide. They are
 * exact to about 2 ulp and give the same bits on every run.
 *
 * Why the clamps work on the bits: under the default -ftrapping-math a
 * float comparison may raise an exception, and GCC then splits
 * `x < c ? c : x` into branches (specialising what follows for the
 * constant) and refuses to vectorise; an unsigned integer min is a plain
 * MIN that never traps. For x <= 0 the bits, read unsigned, grow as x
 * falls (+0 is 0, -0 is 0x80000000), so the unsigned min of the bits is
 * the float max. */
#ifndef NN_FASTMATH_H
#define NN_FASTMATH_H
#include <math.h>
#include <stdint.h>
#include <string.h>

/* The portable build targets plain x86-64 (SSE2, 4 lanes). Hot kernels
 * outside BLAS carry this attribute: GCC compiles them also for AVX2 with
 * FMA (x86-64-v3) and AVX-512 and picks the widest the CPU has when the
 * program starts. nn/ is compiled with -ffp-contract=fast (Makefile), so
 * these clones fuse a * b + c into one multiply-add: twice the arithmetic
 * per instruction, one rounding instead of two. The choice is fixed per
 * machine, so runs stay bit-identical. */
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
#define NN_SIMD_CLONES __attribute__((target_clones("avx512f", "arch=x86-64-v3", "default")))
#else
#define NN_SIMD_CLONES
#endif
/* Helpers of such kernels: a helper compiled on its own gets the plain
 * x86-64 code, so it must be inlined into each clone. */
#define NN_INLINE static inline __attribute__((always_inline))

/* exp(x) for x <= 0 (softmax after max subtraction, sigmoid of -|x|):
 * x = n ln2 + r with |r| <= ln2/2, exp(r) by its Taylor polynomial to
 * degree 7 (truncation 5e-9), 2^n built in the exponent bits. Results
 * below FLT_MIN (x < -87) flush to 0 so that n stays a normal exponent. */
static inline float nn_exp_nonpos(float x) {
    const uint32_t minus_87 = 0xC2AE0000u; /* bits of -87.0f */
    uint32_t xb;
    memcpy(&xb, &x, sizeof xb);
    uint32_t cb = xb < minus_87 ? xb : minus_87;
    float xc;
    memcpy(&xc, &cb, sizeof xc);
    int32_t n = (int32_t)(xc * 1.44269504f - 0.5f); /* round to nearest for xc <= 0 */
    float nf = (float)n;
    float r = xc - nf * 0.693359375f + nf * 2.12194440e-4f; /* ln2 split: hi exact */
    float p = 1.0f / 5040.0f;
    p = p * r + 1.0f / 720.0f;
    p = p * r + 1.0f / 120.0f;
    p = p * r + 1.0f / 24.0f;
    p = p * r + 1.0f / 6.0f;
    p = p * r + 0.5f;
    p = p * r + 1.0f;
    p = p * r + 1.0f;
    uint32_t sb = xb > minus_87 ? 0u : (uint32_t)(n + 127) << 23; /* 2^n, or 0 */
    float scale;
    memcpy(&scale, &sb, sizeof scale);
    return p * scale;
}

/* sigmoid(x) and 1 - sigmoid(x), both without cancellation for any x:
 * with e = exp(-|x|) <= 1 they are 1/(1+e) and e/(1+e), in an order set
 * by the sign. The sign picks by exact weights 0 and 1 rather than by a
 * select, which GCC would turn back into a branch (see the top). */
static inline void nn_sigmoid2(float x, float *s, float *one_minus_s) {
    float e = nn_exp_nonpos(-fabsf(x));
    float big = 1.0f / (1.0f + e), small = e * big;
    uint32_t xb;
    memcpy(&xb, &x, sizeof xb);
    float neg = (float)(xb >> 31);
    *s = neg * small + (1.0f - neg) * big;
    *one_minus_s = neg * big + (1.0f - neg) * small;
}

#endif
