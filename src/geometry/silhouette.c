/* silhouette.c: silhouettes and their distance maps (see silhouette.h). */
#include <math.h>
#include <stdlib.h>
#include "geometry/silhouette.h"

/* Squared Euclidean distance transform of one line (Felzenszwalb and
 * Huttenlocher): d[k] = min_q (k - q)^2 + f[q], with f = INFINITY off the
 * object. v, z: scratch of n and n + 1. */
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

/* distance: squared distances along rows, then along columns, then sqrt. */
static int distance_map(ws_silhouette *s, ws_status *st) {
    const int W = s->width, H = s->height, n = W > H ? W : H;
    float *line = ws_malloc(sizeof(float) * 3 * (n + 1), "distance scratch", st);
    int *v = line ? ws_malloc(sizeof(int) * n, "distance scratch", st) : NULL;
    if (!v) {
        free(line);
        return st->code;
    }
    float *in = line + n + 1, *z = in + n + 1;
    for (int i = 0; i < H; i++) {
        for (int j = 0; j < W; j++) in[j] = s->in[(size_t)i * W + j] ? 0.0f : INFINITY;
        distance_1d(in, W, s->distance + (size_t)i * W, v, z);
    }
    for (int j = 0; j < W; j++) {
        for (int i = 0; i < H; i++) in[i] = s->distance[(size_t)i * W + j];
        distance_1d(in, H, line, v, z);
        for (int i = 0; i < H; i++) s->distance[(size_t)i * W + j] = sqrtf(line[i]);
    }
    free(line);
    free(v);
    return WS_OK;
}

int ws_silhouette_make(const ws_image *photo, const ws_image *mask, ws_silhouette *s,
                       ws_status *st) {
    const int W = photo->width, H = photo->height;
    const size_t hw = (size_t)W * H;
    *s = (ws_silhouette){.width = W, .height = H};
    if (mask && (mask->width != W || mask->height != H))
        return ws_fail(st, WS_EINTERNAL, "silhouette: mask %d x %d for a %d x %d photo",
                       mask->width, mask->height, W, H);
    s->in = ws_malloc(hw, "a silhouette", st);
    s->distance = s->in ? ws_malloc(hw * sizeof(float), "a silhouette distance map", st) : NULL;
    float *border = s->distance ? ws_malloc(sizeof(float) * 2 * (W + H), "border pixels", st) : NULL;
    if (!border) {
        ws_silhouette_free(s);
        return st->code;
    }
    float background[3];
    ws_image_border_median(photo, background, border);
    free(border);
    for (size_t p = 0; p < hw; p++) {
        int object;
        if (mask) {
            object = mask->data[p] >= 0.5f;
        } else {
            double diff = 0;
            for (int c = 0; c < 3; c++) diff = fmax(diff, fabs(photo->data[c * hw + p] - background[c]));
            object = diff > WS_SILHOUETTE_THRESHOLD;
        }
        s->in[p] = (uint8_t)object;
        s->area += object;
        int i = (int)(p / W), j = (int)(p % W);
        s->touches_border |= object && (i == 0 || j == 0 || i == H - 1 || j == W - 1);
    }
    if (distance_map(s, st)) {
        ws_silhouette_free(s);
        return st->code;
    }
    return WS_OK;
}

int ws_view_silhouette(const ws_view *v, ws_silhouette *s, ws_status *st) {
    return ws_silhouette_make(&v->photo, v->mask.data ? &v->mask : NULL, s, st);
}

void ws_silhouette_free(ws_silhouette *s) {
    free(s->in);
    free(s->distance);
    s->in = NULL;
    s->distance = NULL;
}

int ws_split_silhouettes(const ws_split *sp, ws_silhouette **out, ws_status *st) {
    *out = ws_calloc(sp->n ? sp->n : 1, sizeof **out, "silhouettes", st);
    if (!*out) return st->code;
    for (int k = 0; k < sp->n; k++)
        if (ws_view_silhouette(&sp->views[k], &(*out)[k], st)) {
            ws_silhouettes_free(*out, sp->n);
            *out = NULL;
            return st->code;
        }
    return WS_OK;
}

void ws_silhouettes_free(ws_silhouette *s, int n) {
    for (int k = 0; s && k < n; k++) ws_silhouette_free(&s[k]);
    free(s);
}
