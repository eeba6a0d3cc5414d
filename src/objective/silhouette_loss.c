/* silhouette_loss.c: the silhouette-consistency term (see silhouette_loss.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "nn/parallel.h"
#include "objective/silhouette_loss.h"

/* Half a pixel: the extent of an object pixel around its centre. */
#define MARGIN 0.5

struct ws_silhouette_loss {
    const ws_split *split;
    const ws_silhouette *sil; /* one per view, borrowed */
    double *value;        /* cap x 4: each Gaussian's sum over the views, then (from
                             value + cap) its gradient, of the last forward */
    int cap, n, views;    /* Gaussians and views of the last forward */
};

int ws_silhouette_loss_create(ws_silhouette_loss **out, const ws_split *split, const ws_silhouette *sil,
                              ws_status *st) {
    ws_silhouette_loss *s = *out = ws_calloc(1, sizeof *s, "silhouette term", st);
    if (!s) return st->code;
    s->split = split;
    s->sil = sil;
    return WS_OK;
}

void ws_silhouette_loss_free(ws_silhouette_loss *s) {
    if (!s) return;
    free(s->value);
    free(s);
}

/* The distance D at map point (x, y) (pixel centres at integers) and
 * grad = (dD/dx, dD/dy): bilinear inside the map, plus the distance to the
 * map beyond it. Returns -1 where the view has no say (beyond the frame of
 * a silhouette that touches it). */
static double distance_at(const ws_silhouette *m, double x, double y, double grad[2]) {
    const int W = m->width, H = m->height;
    double cx = fmin(fmax(x, 0.0), W - 1.0), cy = fmin(fmax(y, 0.0), H - 1.0);
    double ex = x - cx, ey = y - cy, beyond = ex != 0 || ey != 0 ? sqrt(ex * ex + ey * ey) : 0;
    if (beyond > 0 && m->touches_border) return -1;
    int j = (int)cx, i = (int)cy;
    if (j > W - 2) j = W > 1 ? W - 2 : 0;
    if (i > H - 2) i = H > 1 ? H - 2 : 0;
    int j1 = j + 1 < W ? j + 1 : j, i1 = i + 1 < H ? i + 1 : i;
    double fx = cx - j, fy = cy - i;
    const float *d = m->distance;
    double d00 = d[(size_t)i * W + j], d01 = d[(size_t)i * W + j1];
    double d10 = d[(size_t)i1 * W + j], d11 = d[(size_t)i1 * W + j1];
    double top = d00 + fx * (d01 - d00), bottom = d10 + fx * (d11 - d10);
    /* clamped along an axis: the map's own slope there is 0 */
    grad[0] = ex != 0 ? 0 : (1 - fy) * (d01 - d00) + fy * (d11 - d10);
    grad[1] = ey != 0 ? 0 : bottom - top;
    if (beyond > 0) {
        grad[0] += ex / beyond;
        grad[1] += ey / beyond;
    }
    return top + fy * (bottom - top) + beyond;
}

/* View k's part of the term of Gaussians [g0, g1) of mu, max(0, D_k -
 * 1/2)^2 each, added to value[g], its gradient with respect to mu_g to
 * grad[3 g]. The camera's arithmetic is ws_camera_to_cam and
 * ws_camera_project written out, so that it stays in registers. */
static void view_term(const ws_silhouette_loss *s, int k, const double *mu, int g0, int g1, double *value,
                      double *grad) {
    const ws_camera *cam = &s->split->views[k].cam;
    const ws_silhouette *m = &s->sil[k];
    const double(*R)[3] = cam->R, *t = cam->t, focal = cam->focal;
    const double u0 = cam->cx - WS_PIXEL_CENTER, v0 = cam->cy - WS_PIXEL_CENTER;
    for (int g = g0; g < g1; g++) {
        const double *p = mu + 3 * g;
        double c[3], dD[2];
        for (int a = 0; a < 3; a++) c[a] = R[a][0] * p[0] + R[a][1] * p[1] + R[a][2] * p[2] + t[a];
        double depth = -c[2];
        if (!(depth > 0)) continue;
        double f = focal / depth;
        double excess = distance_at(m, u0 + f * c[0], v0 - f * c[1], dD) - MARGIN;
        if (!(excess > 0)) continue;
        value[g] += excess * excess;
        /* u = cx + f c_x / d, v = cy - f c_y / d, d = -c_z; c = R mu + t */
        double e = 2 * excess * f;
        double dc[3] = {e * dD[0], -e * dD[1], e * (dD[0] * c[0] - dD[1] * c[1]) / depth};
        for (int a = 0; a < 3; a++) grad[3 * g + a] += R[0][a] * dc[0] + R[1][a] * dc[1] + R[2][a] * dc[2];
    }
}

/* Gaussians in blocks of this many: a thread runs through the views for
 * one block at a time, so that neighbouring centres of a curve read
 * neighbouring pixels of one map. */
#define BLOCK 256

int ws_silhouette_loss_stride(int nviews) {
    int stride = (nviews + WS_SILHOUETTE_VIEWS - 1) / WS_SILHOUETTE_VIEWS;
    return stride > 1 ? stride : 1;
}

int ws_silhouette_loss_forward(ws_silhouette_loss *s, const double *mu, int n, int part, double *value,
                               ws_status *st) {
    *value = 0;
    if (n > s->cap) {
        free(s->value);
        s->cap = 2 * n;
        if (!(s->value = ws_malloc((size_t)s->cap * 4 * sizeof(double), "silhouette term values", st))) {
            s->cap = 0;
            return st->code;
        }
    }
    double *val = s->value, *grad = s->value + s->cap;
    const int V = s->split->n, stride = ws_silhouette_loss_stride(V), blocks = (n + BLOCK - 1) / BLOCK;
    const int first = V ? part % stride : 0;
    s->n = n;
    s->views = V > first ? (V - first + stride - 1) / stride : 0;
    #pragma omp parallel for schedule(static) if (nn_fork((size_t)n * s->views))
    for (int b = 0; b < blocks; b++) {
        int g0 = b * BLOCK, g1 = g0 + BLOCK < n ? g0 + BLOCK : n;
        memset(val + g0, 0, (size_t)(g1 - g0) * sizeof *val);
        memset(grad + 3 * (size_t)g0, 0, 3 * (size_t)(g1 - g0) * sizeof *grad);
        for (int k = first; k < V; k += stride)
            if (s->sil[k].area > 0) view_term(s, k, mu, g0, g1, val, grad);
    }
    double sum = 0;
    for (int g = 0; g < n; g++) sum += val[g];
    *value = n && s->views ? sum / ((double)n * s->views) : 0;
    return WS_OK;
}

void ws_silhouette_loss_backward(const ws_silhouette_loss *s, double scale, double *dmu) {
    const double *grad = s->value + s->cap;
    double k = s->n && s->views ? scale / ((double)s->n * s->views) : 0;
    for (int i = 0; i < 3 * s->n; i++) dmu[i] = k * grad[i];
}
