/* similarity.c: mean squared difference and cosine similarity (see
 * similarity.h). Sums run in double: the vectors hold up to 50 x 768
 * floats, where float accumulation would lose digits the tests check. */
#include <math.h>
#include "similarity.h"

#define COSINE_EPS 1e-8

double nn_mse_forward(const float *a, const float *b, size_t n) {
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        double d = (double)a[i] - b[i];
        sum += d * d;
    }
    return sum / (double)n;
}

void nn_mse_backward(const float *a, const float *b, size_t n, float scale, float *da) {
    double k = 2.0 * scale / (double)n;
    for (size_t i = 0; i < n; i++) da[i] = (float)(k * ((double)a[i] - b[i]));
}

typedef struct {
    double dot, norm_a, norm_b; /* norms clamped at COSINE_EPS */
} cosine_parts;

static cosine_parts cosine_parts_of(const float *a, const float *b, size_t n) {
    double dot = 0, aa = 0, bb = 0;
    for (size_t i = 0; i < n; i++) {
        dot += (double)a[i] * b[i];
        aa += (double)a[i] * a[i];
        bb += (double)b[i] * b[i];
    }
    cosine_parts p = {dot, fmax(sqrt(aa), COSINE_EPS), fmax(sqrt(bb), COSINE_EPS)};
    return p;
}

double nn_cosine_forward(const float *a, const float *b, size_t n) {
    cosine_parts p = cosine_parts_of(a, b, n);
    return p.dot / (p.norm_a * p.norm_b);
}

/* d cos / da = b / (|a| |b|) - cos a / |a|^2; where |a| is clamped the
 * second term vanishes (the clamp is constant in a there). */
void nn_cosine_backward(const float *a, const float *b, size_t n, float scale, float *da) {
    cosine_parts p = cosine_parts_of(a, b, n);
    double cosv = p.dot / (p.norm_a * p.norm_b);
    double kb = scale / (p.norm_a * p.norm_b);
    double ka = p.norm_a > COSINE_EPS ? -scale * cosv / (p.norm_a * p.norm_a) : 0.0;
    for (size_t i = 0; i < n; i++) da[i] += (float)(kb * b[i] + ka * a[i]);
}
