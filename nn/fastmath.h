/* fastmath.h: exp and sigmoid in a form the compiler vectorises.
 *
 * glibc's expf is a function call per element, which keeps the loops of
 * quick_gelu and softmax scalar; these inline versions are branch-free, so
 * a `#pragma omp simd` loop runs them 8 or 16 lanes wide. They are exact to
 * about 2 ulp and give the same bits on every run. */
#ifndef NN_FASTMATH_H
#define NN_FASTMATH_H
#include <stdint.h>
#include <string.h>

/* exp(x) for x <= 0 (softmax after max subtraction, sigmoid of -|x|):
 * x = n ln2 + r with |r| <= ln2/2, exp(r) by its Taylor polynomial to
 * degree 7 (truncation 5e-9), 2^n built in the exponent bits. Results
 * below FLT_MIN (x < -87) flush to 0 so that n stays a normal exponent. */
static inline float nn_exp_nonpos(float x) {
    float xc = x < -87.0f ? -87.0f : x;
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
    int32_t bits = (n + 127) << 23;
    float scale;
    memcpy(&scale, &bits, sizeof scale);
    return x < -87.0f ? 0.0f : p * scale;
}

/* sigmoid(x) and 1 - sigmoid(x), both without cancellation for any x:
 * with e = exp(-|x|) <= 1 the two are 1/(1+e) and e/(1+e). */
static inline void nn_sigmoid2(float x, float *s, float *one_minus_s) {
    float e = nn_exp_nonpos(x < 0.0f ? x : -x);
    float big = 1.0f / (1.0f + e), small = e * big;
    *s = x >= 0.0f ? big : small;
    *one_minus_s = x >= 0.0f ? small : big;
}

#endif
