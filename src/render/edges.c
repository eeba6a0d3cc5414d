/* edges.c: the edge map of a photo and the multi-scale blurred L2 loss
 * (definitions in edges.h). */
#include <math.h>
#include <stdlib.h>
#include "render/edges.h"
#include "render/pyramid.h"
#include "nn/parallel.h"

struct ws_edges_workspace {
    int W, H;
    int w[WS_EDGES_LEVELS], h[WS_EDGES_LEVELS]; /* level sizes */
    double *diff[WS_EDGES_LEVELS];  /* D_s, in the backward pass dL/dD_s */
    double *blur[WS_EDGES_LEVELS];  /* G * D_s */
    double *tmp;                    /* the row pass of a blur, H x W */
    double *row_sum;                /* per-row sums of squares, H */
    ws_blur_kernel kernel;
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
#pragma omp parallel for reduction(max : max) if (nn_fork(hw))
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
    if (ws_blur_kernel_init(&ws->kernel, WS_EDGES_SIGMA)) {
        ws_edges_workspace_free(ws);
        return ws_fail(st, WS_EINTERNAL, "edges: blur sigma %g is too large", WS_EDGES_SIGMA);
    }
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

/* diff[0] = alpha - edge, diff[s] = pool(diff[s-1]), blur[s] = G * diff[s]. */
static void pyramid(const double *alpha, const float *edge, ws_edges_workspace *ws) {
    size_t n = (size_t)ws->W * ws->H;
    for (size_t k = 0; k < n; k++) ws->diff[0][k] = alpha[k] - edge[k];
    for (int s = 1; s < WS_EDGES_LEVELS; s++)
        ws_pool2_forward(ws->diff[s - 1], ws->w[s - 1], ws->h[s - 1], ws->diff[s]);
    for (int s = 0; s < WS_EDGES_LEVELS; s++)
        ws_blur_forward(&ws->kernel, ws->diff[s], ws->blur[s], ws->tmp, ws->w[s], ws->h[s]);
}

double ws_edges_loss_forward(const double *alpha, const float *edge, int W, int H,
                             ws_edges_workspace *ws) {
    if (W != ws->W || H != ws->H) return NAN; /* a caller's bug, caught by its finiteness check */
    pyramid(alpha, edge, ws);
    double loss = 0;
    for (int s = 0; s < WS_EDGES_LEVELS; s++) {
        int w = ws->w[s], h = ws->h[s];
        const double *b = ws->blur[s];
#pragma omp parallel for if (nn_fork((size_t)w * h))
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
        ws_blur_forward(&ws->kernel, ws->blur[s], ws->diff[s], ws->tmp, ws->w[s], ws->h[s]);
    }
    /* Through the pooling, coarsest first: each child gets its cell's
     * gradient divided by the cell's pixel count. */
    for (int s = WS_EDGES_LEVELS - 1; s > 0; s--)
        ws_pool2_backward(ws->diff[s], ws->w[s - 1], ws->h[s - 1], ws->diff[s - 1]);
    for (size_t k = 0; k < n; k++) dalpha[k] = ws->diff[0][k];
}
