/* thin_edges.c: Canny edges with self-relative thresholds (see
 * thin_edges.h). Called once per view, so its buffers are allocated per
 * call. Serial where order matters (the quantile, the flood fill), so the
 * map does not depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "render/pyramid.h"
#include "render/thin_edges.h"
#include "nn/parallel.h"
#include "base/sort.h"

/* Sobel gradient of s (H x W): its magnitude into m (H x W), its
 * direction's sector (0..3, as a double) into sector (H x W). */
static void gradient(const double *s, int W, int H, double *m, double *sector) {
#pragma omp parallel for if (nn_fork((size_t)W * H))
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            double v[3][3];
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    v[a][b] = s[(size_t)ws_repeat_index(i + a - 1, H) * W + ws_repeat_index(j + b - 1, W)];
            double gx = ((v[0][2] + 2 * v[1][2] + v[2][2]) - (v[0][0] + 2 * v[1][0] + v[2][0])) / 8;
            double gy = ((v[2][0] + 2 * v[2][1] + v[2][2]) - (v[0][0] + 2 * v[0][1] + v[0][2])) / 8;
            m[(size_t)i * W + j] = sqrt(gx * gx + gy * gy);
            double angle = atan2(gy, gx); /* rows down, columns right */
            int d = (int)lround(angle / (M_PI / 4));
            sector[(size_t)i * W + j] = ((d % 4) + 4) % 4;
        }
}

/* Non-maximum suppression: ridge (H x W) is 1 where the magnitude m
 * (H x W) is at least both neighbours across its sector's direction (ties
 * go forward) and above WS_THIN_FLOOR of the largest. */
static void suppress(const double *m, const double *sector, int W, int H, unsigned char *ridge) {
    const size_t n = (size_t)W * H;
    /* steps (di, dj) of the 4 sectors */
    static const int step[4][2] = {{0, 1}, {1, 1}, {1, 0}, {1, -1}};
    double top = 0;
    for (size_t k = 0; k < n; k++) top = fmax(top, m[k]);
#pragma omp parallel for if (nn_fork(n))
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            size_t at = (size_t)i * W + j;
            int d = (int)sector[at];
            int i1 = i + step[d][0], j1 = j + step[d][1], i2 = i - step[d][0], j2 = j - step[d][1];
            double fwd = i1 >= 0 && i1 < H && j1 >= 0 && j1 < W ? m[(size_t)i1 * W + j1] : 0;
            double back = i2 >= 0 && i2 < H && j2 >= 0 && j2 < W ? m[(size_t)i2 * W + j2] : 0;
            ridge[at] = m[at] > WS_THIN_FLOOR * top && m[at] >= fwd && m[at] > back;
        }
}

/* Hysteresis with thresholds from the ridge pixels' own strengths: edge
 * (H x W) is 1 on the ridge pixels at least the WS_THIN_HIGH quantile
 * strong and on those at least WS_THIN_LOW of it that connect to them,
 * 0 elsewhere. strengths (H x W doubles) and stack (H x W ints) are
 * scratch. Serial: the quantile and the flood fill. */
static void hysteresis(const double *m, const unsigned char *ridge, int W, int H, double *strengths, int *stack,
                       float *edge) {
    const size_t n = (size_t)W * H;
    size_t count = 0;
    for (size_t k = 0; k < n; k++)
        if (ridge[k]) strengths[count++] = m[k];
    memset(edge, 0, n * sizeof *edge);
    if (count == 0) return;
    ws_sort_doubles(strengths, count);
    size_t rank = (size_t)ceil(WS_THIN_HIGH * count); /* nearest rank, 1-based */
    double high = strengths[rank > 0 ? rank - 1 : 0], low = WS_THIN_LOW * high;
    /* flood from the strong ridge pixels through the weak ones */
    int top_of_stack = 0;
    for (size_t k = 0; k < n; k++)
        if (ridge[k] && m[k] >= high) {
            edge[k] = 1;
            stack[top_of_stack++] = (int)k;
        }
    while (top_of_stack > 0) {
        int k = stack[--top_of_stack], i = k / W, j = k % W;
        for (int a = -1; a <= 1; a++)
            for (int b = -1; b <= 1; b++) {
                int ii = i + a, jj = j + b;
                if (ii < 0 || ii >= H || jj < 0 || jj >= W) continue;
                size_t q = (size_t)ii * W + jj;
                if (ridge[q] && !edge[q] && m[q] >= low) {
                    edge[q] = 1;
                    stack[top_of_stack++] = (int)q;
                }
            }
    }
}

int ws_thin_edges(const float *photo, int W, int H, float *edge, ws_status *st) {
    const size_t n = (size_t)W * H;
    double *y = ws_malloc(n * sizeof *y, "edge detection", st);
    double *s = y ? ws_malloc(n * sizeof *s, "edge detection", st) : NULL;
    double *m = s ? ws_malloc(n * sizeof *m, "edge detection", st) : NULL;
    unsigned char *ridge = m ? ws_calloc(n, 1, "edge detection", st) : NULL;
    int *stack = ridge ? ws_malloc(n * sizeof *stack, "edge detection", st) : NULL;
    if (stack) {
        ws_blur_kernel g;
        ws_blur_kernel_init(&g, WS_THIN_SIGMA);
        for (size_t k = 0; k < n; k++) y[k] = 0.299 * photo[k] + 0.587 * photo[n + k] + 0.114 * photo[2 * n + k];
        ws_blur_repeat_forward(&g, y, s, m, W, H);
        gradient(s, W, H, m, y); /* y (the luminance) is free now */
        suppress(m, y, W, H, ridge);
        hysteresis(m, ridge, W, H, s, stack, edge); /* s too */
    }
    int rc = stack ? WS_OK : st->code;
    free(y);
    free(s);
    free(m);
    free(ridge);
    free(stack);
    return rc;
}

void ws_thin_edges_add_outline(const float *mask, int W, int H, float *edge) {
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            size_t at = (size_t)i * W + j;
            if (!(mask[at] >= 0.5f)) continue;
            int outline = (i > 0 && mask[at - W] < 0.5f) || (i + 1 < H && mask[at + W] < 0.5f) ||
                          (j > 0 && mask[at - 1] < 0.5f) || (j + 1 < W && mask[at + 1] < 0.5f);
            if (outline) edge[at] = 1;
        }
}
