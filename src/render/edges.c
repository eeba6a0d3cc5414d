/* edges.c: the edge map of a photo and the multi-scale blurred L2 loss
 * (definitions in edges.h). */
#include <math.h>
#include <stdlib.h>
#include "render/edges.h"

#define MAX_RADIUS 16 /* bounds ceil(3 * WS_EDGES_SIGMA) */

struct ws_edges_workspace {
    int W, H;
    int w[WS_EDGES_LEVELS], h[WS_EDGES_LEVELS]; /* level sizes */
    double *diff[WS_EDGES_LEVELS];  /* D_s, in the backward pass dL/dD_s */
    double *blur[WS_EDGES_LEVELS];  /* G * D_s */
    double *tmp;                    /* the row pass of a blur, H x W */
    double *row_sum;                /* per-row sums of squares, H */
    int radius;
    double kernel[2 * MAX_RADIUS + 1];
};

static float luminance(const float *photo, size_t hw, int W, int H, int i, int j) {
    i = i < 0 ? 0 : i >= H ? H - 1 : i;
    j = j < 0 ? 0 : j >= W ? W - 1 : j;
    size_t k = (size_t)i * W + j;
    return 0.299f * photo[k] + 0.587f * photo[hw + k] + 0.114f * photo[2 * hw + k];
}

void ws_edges_target(const float *photo, int W, int H, float *edge) {
    size_t hw = (size_t)W * H;
    float max = 0;
#pragma omp parallel for reduction(max : max)
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            float y[3][3];
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) y[a][b] = luminance(photo, hw, W, H, i + a - 1, j + b - 1);
            float gx = (y[0][2] + 2 * y[1][2] + y[2][2]) - (y[0][0] + 2 * y[1][0] + y[2][0]);
            float gy = (y[2][0] + 2 * y[2][1] + y[2][2]) - (y[0][0] + 2 * y[0][1] + y[0][2]);
            float m = sqrtf(gx * gx + gy * gy);
            edge[(size_t)i * W + j] = m;
            if (m > max) max = m;
        }
    if (!(max > 0)) return;
    /* The scale is the mean magnitude of the clear edges (above a tenth of
     * the strongest), not the maximum: a stroke costs about 1 per pixel
     * wherever it lies, so it must also earn about 1 on a typical edge, or
     * an empty sketch would beat a right one. Summed serially: the same
     * bits for any thread count. */
    double sum = 0;
    long count = 0;
    for (size_t k = 0; k < hw; k++)
        if (edge[k] > 0.1f * max) {
            sum += edge[k];
            count++;
        }
    float scale = (float)(sum / count);
    for (size_t k = 0; k < hw; k++) edge[k] = fminf(1.0f, edge[k] / scale);
}

int ws_edges_workspace_create(ws_edges_workspace **out, int W, int H, ws_status *st) {
    *out = NULL;
    if (W < 1 || H < 1)
        return ws_fail(st, WS_EINTERNAL, "edges: workspace for an empty %dx%d image", W, H);
    ws_edges_workspace *ws = ws_calloc(1, sizeof *ws, "edges workspace", st);
    if (!ws) return st->code;
    ws->W = W;
    ws->H = H;
    int ok = (ws->tmp = ws_malloc((size_t)W * H * sizeof(double), "edges workspace", st)) &&
             (ws->row_sum = ws_malloc((size_t)H * sizeof(double), "edges workspace", st));
    for (int s = 0; s < WS_EDGES_LEVELS && ok; s++) {
        ws->w[s] = s ? (ws->w[s - 1] + 1) / 2 : W;
        ws->h[s] = s ? (ws->h[s - 1] + 1) / 2 : H;
        size_t n = (size_t)ws->w[s] * ws->h[s] * sizeof(double);
        ok = (ws->diff[s] = ws_malloc(n, "edges workspace", st)) &&
             (ws->blur[s] = ws_malloc(n, "edges workspace", st));
    }
    if (!ok) {
        ws_edges_workspace_free(ws);
        return st->code;
    }
    ws->radius = (int)ceil(3 * WS_EDGES_SIGMA);
    if (ws->radius > MAX_RADIUS) {
        ws_edges_workspace_free(ws);
        return ws_fail(st, WS_EINTERNAL, "edges: blur sigma %g is too large", WS_EDGES_SIGMA);
    }
    double sum = 0;
    for (int t = -ws->radius; t <= ws->radius; t++)
        sum += ws->kernel[t + ws->radius] = exp(-t * t / (2 * WS_EDGES_SIGMA * WS_EDGES_SIGMA));
    for (int t = 0; t <= 2 * ws->radius; t++) ws->kernel[t] /= sum;
    *out = ws;
    return WS_OK;
}

void ws_edges_workspace_free(ws_edges_workspace *ws) {
    if (!ws) return;
    for (int s = 0; s < WS_EDGES_LEVELS; s++) {
        free(ws->diff[s]);
        free(ws->blur[s]);
    }
    free(ws->tmp);
    free(ws->row_sum);
    free(ws);
}

/* out = G * in on a w x h image, zero outside; out may be in. The kernel is
 * symmetric and the padding zero, so this map is its own transpose. */
static void blur(const ws_edges_workspace *ws, const double *in, double *out, int w, int h) {
    const int R = ws->radius;
    const double *k = ws->kernel + R;
    double *tmp = ws->tmp;
#pragma omp parallel for
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double s = 0;
            for (int t = j - R < 0 ? -j : -R; t <= R && j + t < w; t++) s += k[t] * in[(size_t)i * w + j + t];
            tmp[(size_t)i * w + j] = s;
        }
#pragma omp parallel for
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double s = 0;
            for (int t = i - R < 0 ? -i : -R; t <= R && i + t < h; t++) s += k[t] * tmp[(size_t)(i + t) * w + j];
            out[(size_t)i * w + j] = s;
        }
}

/* Number of pixels of a w x h image that pooled cell (i, j) covers. */
static int cell_count(int w, int h, int i, int j) {
    return (2 * i + 1 < h ? 2 : 1) * (2 * j + 1 < w ? 2 : 1);
}

/* diff[0] = alpha - edge, diff[s] = pool(diff[s-1]), blur[s] = G * diff[s]. */
static void pyramid(const double *alpha, const float *edge, ws_edges_workspace *ws) {
    size_t n = (size_t)ws->W * ws->H;
    for (size_t k = 0; k < n; k++) ws->diff[0][k] = alpha[k] - edge[k];
    for (int s = 1; s < WS_EDGES_LEVELS; s++) {
        int wi = ws->w[s - 1], hi = ws->h[s - 1], wo = ws->w[s];
        const double *in = ws->diff[s - 1];
        double *out = ws->diff[s];
#pragma omp parallel for
        for (int i = 0; i < ws->h[s]; i++)
            for (int j = 0; j < wo; j++) {
                double sum = 0;
                for (int a = 2 * i; a < 2 * i + 2 && a < hi; a++)
                    for (int b = 2 * j; b < 2 * j + 2 && b < wi; b++) sum += in[(size_t)a * wi + b];
                out[(size_t)i * wo + j] = sum / cell_count(wi, hi, i, j);
            }
    }
    for (int s = 0; s < WS_EDGES_LEVELS; s++) blur(ws, ws->diff[s], ws->blur[s], ws->w[s], ws->h[s]);
}

double ws_edges_loss_forward(const double *alpha, const float *edge, int W, int H,
                             ws_edges_workspace *ws) {
    if (W != ws->W || H != ws->H) return NAN; /* a caller's bug, caught by its finiteness check */
    pyramid(alpha, edge, ws);
    double loss = 0;
    for (int s = 0; s < WS_EDGES_LEVELS; s++) {
        int w = ws->w[s], h = ws->h[s];
        const double *b = ws->blur[s];
#pragma omp parallel for
        for (int i = 0; i < h; i++) {
            double sum = 0;
            for (int j = 0; j < w; j++) sum += b[(size_t)i * w + j] * b[(size_t)i * w + j];
            ws->row_sum[i] = sum;
        }
        double sum = 0;
        for (int i = 0; i < h; i++) sum += ws->row_sum[i];
        loss += sum / ((double)w * h * WS_EDGES_LEVELS);
    }
    return loss;
}

void ws_edges_loss_backward(const double *alpha, const float *edge, int W, int H,
                            ws_edges_workspace *ws, double *dalpha) {
    size_t n = (size_t)W * H;
    if (W != ws->W || H != ws->H) {
        for (size_t k = 0; k < n; k++) dalpha[k] = NAN;
        return;
    }
    pyramid(alpha, edge, ws);
    /* dL/dD_s = 2 / (S n_s) G^T (G * D_s), G^T = G; kept in diff[s]. */
    for (int s = 0; s < WS_EDGES_LEVELS; s++) {
        size_t ns = (size_t)ws->w[s] * ws->h[s];
        double scale = 2.0 / ((double)ns * WS_EDGES_LEVELS);
        for (size_t k = 0; k < ns; k++) ws->blur[s][k] *= scale;
        blur(ws, ws->blur[s], ws->diff[s], ws->w[s], ws->h[s]);
    }
    /* Through the pooling, coarsest first: each child gets its cell's
     * gradient divided by the cell's pixel count. */
    for (int s = WS_EDGES_LEVELS - 1; s > 0; s--) {
        int wi = ws->w[s - 1], hi = ws->h[s - 1], wo = ws->w[s];
        const double *g = ws->diff[s];
        double *gin = ws->diff[s - 1];
#pragma omp parallel for
        for (int a = 0; a < hi; a++)
            for (int b = 0; b < wi; b++)
                gin[(size_t)a * wi + b] +=
                    g[(size_t)(a / 2) * wo + b / 2] / cell_count(wi, hi, a / 2, b / 2);
    }
    for (size_t k = 0; k < n; k++) dalpha[k] = ws->diff[0][k];
}
