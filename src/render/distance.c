/* distance.c: the Euclidean distance transform (see distance.h). */
#include <math.h>
#include <stdlib.h>
#include "render/distance.h"

/* Squared Euclidean distance transform of one line (Felzenszwalb and
 * Huttenlocher): d[k] = min_q (k - q)^2 + f[q], with f = INFINITY off the
 * set. v, z: scratch of n and n + 1. */
static void distance_1d(const float *f, int n, float *d, int *v, float *z) {
    int k = -1;
    for (int q = 0; q < n; q++) {
        if (!isfinite(f[q])) continue;
        float s = 0;
        while (k >= 0) {
            s = ((f[q] + (float)q * q) - (f[v[k]] + (float)v[k] * v[k])) / (2.0f * (q - v[k]));
            if (s > z[k]) break;
            k--;
        }
        k++;
        v[k] = q;
        z[k] = k ? s : -INFINITY;
        z[k + 1] = INFINITY;
    }
    if (k < 0) {
        for (int q = 0; q < n; q++) d[q] = INFINITY;
        return;
    }
    for (int q = 0, j = 0; q < n; q++) {
        while (z[j + 1] < q) j++;
        float dq = (float)(q - v[j]);
        d[q] = dq * dq + f[v[j]];
    }
}

/* squared distances along rows, then along columns, then sqrt */
int ws_distance_map(const uint8_t *set, int W, int H, float *distance, ws_status *st) {
    const int n = W > H ? W : H;
    float *line = ws_malloc(sizeof(float) * 3 * (n + 1), "distance scratch", st);
    int *v = line ? ws_malloc(sizeof(int) * n, "distance scratch", st) : NULL;
    if (!v) {
        free(line);
        return st->code;
    }
    float *in = line + n + 1, *z = in + n + 1;
    for (int i = 0; i < H; i++) {
        for (int j = 0; j < W; j++) in[j] = set[(size_t)i * W + j] ? 0.0f : INFINITY;
        distance_1d(in, W, distance + (size_t)i * W, v, z);
    }
    for (int j = 0; j < W; j++) {
        for (int i = 0; i < H; i++) in[i] = distance[(size_t)i * W + j];
        distance_1d(in, H, line, v, z);
        for (int i = 0; i < H; i++) distance[(size_t)i * W + j] = sqrtf(line[i]);
    }
    free(line);
    free(v);
    return WS_OK;
}
