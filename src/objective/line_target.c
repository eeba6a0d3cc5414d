/* line_target.c: thin edges, with the thin parts drawn by their axes (see
 * line_target.h). Called once per view, so its buffers are allocated per
 * call. */
#include <math.h>
#include <stdlib.h>
#include "render/distance.h"
#include "objective/line_evidence.h"
#include "objective/line_target.h"
#include "render/thin_edges.h"

/* Whether pixel (i, j) is on the ridge of the distance map d (line_target.h). */
static int is_axis(const float *d, int W, int H, int i, int j) {
    static const int step[4][2] = {{0, 1}, {1, 1}, {1, 0}, {1, -1}};
    float here = d[(size_t)i * W + j], top = 0;
    int peak = 0;
    for (int k = 0; k < 4; k++) {
        int i1 = i + step[k][0], j1 = j + step[k][1], i2 = i - step[k][0], j2 = j - step[k][1];
        float fwd = i1 >= 0 && i1 < H && j1 >= 0 && j1 < W ? d[(size_t)i1 * W + j1] : 0;
        float back = i2 >= 0 && i2 < H && j2 >= 0 && j2 < W ? d[(size_t)i2 * W + j2] : 0;
        peak |= here >= fwd && here > back;
        top = fmaxf(top, fmaxf(fwd, back));
    }
    return peak && here >= top - WS_THIN_AXIS_SLACK;
}

/* Keeps the 8-connected components of set (values 0/1) that have at least
 * min_area pixels. stack: W x H ints; a component's pixels are kept at its
 * far end while its flood fill uses the near end (2 = reached). */
static void keep_large(uint8_t *set, int W, int H, double min_area, int *stack) {
    const size_t n = (size_t)W * H;
    for (size_t start = 0; start < n; start++) {
        if (set[start] != 1) continue;
        size_t top = 0, count = 0;
        stack[top++] = (int)start;
        set[start] = 2;
        while (top > 0) {
            int k = stack[--top], i = k / W, j = k % W;
            stack[n - 1 - count++] = k;
            for (int a = -1; a <= 1; a++)
                for (int b = -1; b <= 1; b++) {
                    int ii = i + a, jj = j + b;
                    if (ii < 0 || ii >= H || jj < 0 || jj >= W || set[(size_t)ii * W + jj] != 1) continue;
                    set[(size_t)ii * W + jj] = 2;
                    stack[top++] = ii * W + jj;
                }
        }
        uint8_t keep = count >= min_area ? 3 : 0;
        for (size_t c = 0; c < count; c++) set[stack[n - 1 - c]] = keep;
    }
    for (size_t p = 0; p < n; p++) set[p] = set[p] == 3;
}

int ws_line_target(const ws_image *photo, const ws_image *mask, const ws_silhouette *sil, const uint8_t *support,
                   float *edge, ws_status *st) {
    const int W = photo->width, H = photo->height;
    const size_t n = (size_t)W * H;
    if ((mask && (mask->width != W || mask->height != H)) || sil->width != W || sil->height != H)
        return ws_fail(st, WS_EINTERNAL, "line target: a mask or silhouette of another size than the %d x %d photo",
                       W, H);
    if (ws_thin_edges(photo->data, W, H, edge, st)) return st->code;
    if (mask) ws_thin_edges_add_outline(mask->data, W, H, edge);
    uint8_t *set = ws_malloc(n, "line target", st);
    float *inner = set ? ws_malloc(n * sizeof *inner, "line target", st) : NULL;
    float *opened = inner ? ws_malloc(n * sizeof *opened, "line target", st) : NULL;
    float *near = opened ? ws_malloc(n * sizeof *near, "line target", st) : NULL;
    int *stack = near ? ws_malloc(n * sizeof *stack, "line target", st) : NULL;
    int rc = stack ? WS_OK : st->code;
    const double r = WS_THIN_PART_WIDTH / 2 * (W > H ? W : H);
    /* inner = D, the distance to the background */
    if (!rc) {
        for (size_t p = 0; p < n; p++) set[p] = !sil->in[p];
        rc = ws_distance_map(set, W, H, inner, st);
    }
    /* opened: the distance to the eroded object (D > r); O is where it is <= r */
    if (!rc) {
        for (size_t p = 0; p < n; p++) set[p] = inner[p] > r;
        rc = ws_distance_map(set, W, H, opened, st);
    }
    /* set = T; near: the distance to it */
    if (!rc) {
        for (size_t p = 0; p < n; p++) set[p] = sil->in[p] && !(opened[p] <= r);
        keep_large(set, W, H, r * r, stack);
        rc = ws_distance_map(set, W, H, near, st);
    }
    if (!rc)
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++) {
                size_t p = (size_t)i * W + j;
                if (near[p] <= WS_THIN_PART_MARGIN && (set[p] || !sil->in[p])) edge[p] = 0;
                if (set[p] && is_axis(inner, W, H, i, j)) edge[p] = 1;
                if (support && sil->in[p] && !set[p] && inner[p] > WS_EVIDENCE_OUTLINE_PX && !support[p]) edge[p] = 0;
            }
    free(set);
    free(inner);
    free(opened);
    free(near);
    free(stack);
    return rc;
}
