/* lines.c: the line-drawing loss (see lines.h). Forward and backward in one
 * call: the backward needs every level's sums, which the forward has just
 * made. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "objective/lines.h"
#include "render/pyramid.h"
#include "nn/parallel.h"

struct ws_lines_workspace {
    int W, H;
    int w[WS_LINES_LEVELS], h[WS_LINES_LEVELS];
    double *a[WS_LINES_LEVELS];  /* A_s; in the backward pass dL/dA_s */
    double *e[WS_LINES_LEVELS];  /* E_s */
    double *ab[WS_LINES_LEVELS]; /* a_s = G * A_s; in the backward pass dL/da_s */
    double *eb[WS_LINES_LEVELS]; /* e_s = G * E_s */
    double *tmp;                 /* H x W: the row pass of a blur */
    double *rows;                /* 3 x H: per-row sums */
    ws_blur_kernel kernel;
};

void ws_lines_weights(double progress, double w[WS_LINES_LEVELS]) {
    double p = fmin(1, fmax(0, progress));
    double f = (WS_LINES_LEVELS - 1) * fmax(0, 1 - p / WS_LINES_COARSE_END);
    for (int s = 0; s < WS_LINES_LEVELS; s++) w[s] = fmin(1, fmax(0, 1 + s - f));
}

int ws_lines_workspace_create(ws_lines_workspace **out, int W, int H, ws_status *st) {
    *out = NULL;
    if (W < 1 || H < 1) return ws_fail(st, WS_EINTERNAL, "lines: workspace for an empty %dx%d image", W, H);
    ws_lines_workspace *ws = ws_calloc(1, sizeof *ws, "line loss workspace", st);
    if (!ws) return st->code;
    ws->W = W;
    ws->H = H;
    ws_blur_kernel_init(&ws->kernel, WS_LINES_SIGMA);
    int ok = (ws->tmp = ws_malloc((size_t)W * H * sizeof(double), "line loss workspace", st)) &&
             (ws->rows = ws_malloc((size_t)3 * H * sizeof(double), "line loss workspace", st));
    for (int s = 0; s < WS_LINES_LEVELS && ok; s++) {
        ws->w[s] = s ? (ws->w[s - 1] + 1) / 2 : W;
        ws->h[s] = s ? (ws->h[s - 1] + 1) / 2 : H;
        size_t n = (size_t)ws->w[s] * ws->h[s] * sizeof(double);
        ok = (ws->a[s] = ws_malloc(n, "line loss workspace", st)) &&
             (ws->e[s] = ws_malloc(n, "line loss workspace", st)) &&
             (ws->ab[s] = ws_malloc(n, "line loss workspace", st)) &&
             (ws->eb[s] = ws_malloc(n, "line loss workspace", st));
    }
    if (!ok) {
        ws_lines_workspace_free(ws);
        return st->code;
    }
    *out = ws;
    return WS_OK;
}

void ws_lines_workspace_free(ws_lines_workspace *ws) {
    if (!ws) return;
    for (int s = 0; s < WS_LINES_LEVELS; s++) {
        free(ws->a[s]);
        free(ws->e[s]);
        free(ws->ab[s]);
        free(ws->eb[s]);
    }
    free(ws->tmp);
    free(ws->rows);
    free(ws);
}

/* <x, y>, <x, x>, <y, y> of two w x h images, summed per row, then rows in
 * order (the same bits on any team). */
static void dots(const double *x, const double *y, int w, int h, double *rows, double out[3]) {
#pragma omp parallel for if (nn_fork((size_t)w * h))
    for (int i = 0; i < h; i++) {
        double xy = 0, xx = 0, yy = 0;
        for (int j = 0; j < w; j++) {
            double a = x[(size_t)i * w + j], b = y[(size_t)i * w + j];
            xy += a * b;
            xx += a * a;
            yy += b * b;
        }
        rows[3 * i] = xy;
        rows[3 * i + 1] = xx;
        rows[3 * i + 2] = yy;
    }
    out[0] = out[1] = out[2] = 0;
    for (int i = 0; i < h; i++)
        for (int k = 0; k < 3; k++) out[k] += rows[3 * i + k];
}

double ws_lines_loss(const double *alpha, const float *edge, const double w[WS_LINES_LEVELS],
                     ws_lines_workspace *ws, double *dalpha) {
    size_t n = (size_t)ws->W * ws->H;
    double wsum = 0;
    for (int s = 0; s < WS_LINES_LEVELS; s++) wsum += w[s];
    memcpy(ws->a[0], alpha, n * sizeof(double));
    for (size_t k = 0; k < n; k++) ws->e[0][k] = edge[k];
    double loss = 0, g[WS_LINES_LEVELS][3];
    for (int s = 0; s < WS_LINES_LEVELS; s++) {
        int wd = ws->w[s], ht = ws->h[s];
        if (s > 0) {
            ws_pool2_forward(ws->a[s - 1], ws->w[s - 1], ws->h[s - 1], ws->a[s]);
            ws_pool2_forward(ws->e[s - 1], ws->w[s - 1], ws->h[s - 1], ws->e[s]);
        }
        if (w[s] == 0) continue;
        ws_blur_forward(&ws->kernel, ws->a[s], ws->ab[s], ws->tmp, wd, ht);
        ws_blur_forward(&ws->kernel, ws->e[s], ws->eb[s], ws->tmp, wd, ht);
        double d[3], eps = WS_LINES_EPS * wd * ht;
        dots(ws->ab[s], ws->eb[s], wd, ht, ws->rows, d);
        double na = sqrt(d[1] + eps), ne = sqrt(d[2] + eps);
        loss += w[s] / wsum * (1 - d[0] / (na * ne));
        /* dc/da = e / (|a| |e|) - <a, e> a / (|a|^3 |e|); dL/da = -w / wsum dc/da */
        g[s][0] = -w[s] / wsum / (na * ne);
        g[s][1] = w[s] / wsum * d[0] / (na * na * na * ne);
    }
    if (!dalpha) return loss;
    for (int s = WS_LINES_LEVELS - 1; s >= 0; s--) {
        int wd = ws->w[s], ht = ws->h[s];
        size_t ns = (size_t)wd * ht;
        /* ws->a[s] becomes dL/dA_s: the blur's adjoint of dL/da_s, plus what
         * the coarser level passed down through its pooling */
        double *da = ws->a[s];
        if (w[s] != 0) {
            for (size_t k = 0; k < ns; k++) ws->ab[s][k] = g[s][0] * ws->eb[s][k] + g[s][1] * ws->ab[s][k];
            ws_blur_forward(&ws->kernel, ws->ab[s], ws->ab[s], ws->tmp, wd, ht);
        } else {
            memset(ws->ab[s], 0, ns * sizeof(double));
        }
        if (s + 1 < WS_LINES_LEVELS) {
            memset(da, 0, ns * sizeof(double));
            ws_pool2_backward(ws->a[s + 1], wd, ht, da);
            for (size_t k = 0; k < ns; k++) da[k] += ws->ab[s][k];
        } else {
            memcpy(da, ws->ab[s], ns * sizeof(double));
        }
    }
    memcpy(dalpha, ws->a[0], n * sizeof(double));
    return loss;
}
