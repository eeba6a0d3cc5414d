/* line_drawing.c: reference lines from a geometry buffer (see
 * line_drawing.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "io/ref_lines.h"
#include "render/skeleton.h"
#include "synth/line_drawing.h"

int ws_geometry_buffer_alloc(ws_geometry_buffer *g, int width, int height, ws_status *st) {
    const size_t n = (size_t)width * height;
    memset(g, 0, sizeof *g);
    g->width = width;
    g->height = height;
    g->coverage = ws_malloc(n * sizeof(float), "a geometry buffer", st);
    g->depth = g->coverage ? ws_malloc(n * sizeof(float), "a geometry buffer", st) : NULL;
    g->normal = g->depth ? ws_malloc(3 * n * sizeof(float), "a geometry buffer", st) : NULL;
    if (!g->normal) {
        ws_geometry_buffer_free(g);
        return st->code;
    }
    return WS_OK;
}

void ws_geometry_buffer_free(ws_geometry_buffer *g) {
    free(g->coverage);
    free(g->depth);
    free(g->normal);
    g->coverage = g->depth = g->normal = NULL;
}

void ws_synth_resolve_rows(const double *depth, const float *shade, const float *normal, int ss, int top, int rows,
                           const float colour[3], const ws_image *background, const ws_camera *cam, ws_image *img,
                           ws_geometry_buffer *g) {
    const int W = img->width, W2 = W * ss;
    const size_t plane = (size_t)W * img->height;
    for (int i = top; i < top + rows; i++)
        for (int j = 0; j < W; j++) {
            double lit = 0;
            int miss = 0;
            for (int a = 0; a < ss; a++)
                for (int b = 0; b < ss; b++) {
                    const size_t at = (size_t)((i - top) * ss + a) * W2 + j * ss + b;
                    lit += shade[at];
                    miss += isinf(depth[at]);
                }
            for (int c = 0; c < 3; c++)
                img->data[c * plane + (size_t)i * W + j] =
                    (float)((colour[c] * lit + background->data[c * plane + (size_t)i * W + j] * miss) / (ss * ss));
            if (g) {
                const size_t mid = (size_t)((i - top) * ss + ss / 2) * W2 + j * ss + ss / 2;
                ws_geometry_buffer_set(g, cam, i, j, (float)(ss * ss - miss) / (ss * ss), depth[mid], normal + 3 * mid);
            }
        }
}

void ws_geometry_buffer_set(ws_geometry_buffer *g, const ws_camera *cam, int i, int j, float coverage, double depth,
                            const float n[3]) {
    const size_t plane = (size_t)g->width * g->height, at = (size_t)i * g->width + j;
    int hit = isfinite(depth);
    g->coverage[at] = coverage;
    g->depth[at] = hit ? (float)depth : INFINITY;
    /* world = R^T camera */
    for (int x = 0; x < 3; x++)
        g->normal[x * plane + at] = hit ? (float)(cam->R[0][x] * n[0] + cam->R[1][x] * n[1] + cam->R[2][x] * n[2]) : 0;
}

/* cos of the angle between the normals of pixels p and q. */
static double cos_normals(const ws_geometry_buffer *g, size_t p, size_t q) {
    const size_t plane = (size_t)g->width * g->height;
    double d = 0;
    for (int c = 0; c < 3; c++) d += (double)g->normal[c * plane + p] * g->normal[c * plane + q];
    return d;
}

/* Drops the 8-connected components of set with fewer than min_size pixels.
 * stack: W x H ints; mark: W x H bytes of scratch. */
static void drop_specks(uint8_t *set, int W, int H, int min_size, int *stack, uint8_t *mark) {
    const size_t n = (size_t)W * H;
    memset(mark, 0, n);
    for (size_t start = 0; start < n; start++) {
        if (!set[start] || mark[start]) continue;
        size_t top = 0, count = 0;
        stack[top++] = (int)start;
        mark[start] = 1;
        while (top > count) { /* stack[0 .. top) holds the component, [count, top) unvisited */
            int k = stack[count++], i = k / W, j = k % W;
            for (int a = -1; a <= 1; a++)
                for (int b = -1; b <= 1; b++) {
                    int ii = i + a, jj = j + b;
                    if (ii < 0 || ii >= H || jj < 0 || jj >= W) continue;
                    size_t q = (size_t)ii * W + jj;
                    if (!set[q] || mark[q]) continue;
                    mark[q] = 1;
                    stack[top++] = (int)q;
                }
        }
        if (count < (size_t)min_size)
            for (size_t c = 0; c < count; c++) set[stack[c]] = 0;
    }
}

int ws_line_drawing(const ws_geometry_buffer *g, uint8_t *part, ws_status *st) {
    const int W = g->width, H = g->height;
    const size_t n = (size_t)W * H;
    uint8_t *line = ws_malloc(n, "reference lines", st);
    uint8_t *mark = line ? ws_malloc(n, "reference lines", st) : NULL;
    int *stack = mark ? ws_malloc(n * sizeof *stack, "reference lines", st) : NULL;
    if (!stack) {
        free(line);
        free(mark);
        return st->code;
    }
    const double crease = cos(WS_LINE_CREASE_ANGLE * M_PI / 180), flat = cos(WS_LINE_FLAT_ANGLE * M_PI / 180);
    static const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
    for (size_t p = 0; p < n; p++) part[p] = g->coverage[p] > 0.5f ? WS_PART_MASK : WS_PART_BACKGROUND;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            size_t p = (size_t)i * W + j;
            if (part[p] != WS_PART_MASK) continue;
            int kind = WS_PART_MASK;
            for (int k = 0; k < 4; k++) {
                int ii = i + di[k], jj = j + dj[k];
                if (ii < 0 || ii >= H || jj < 0 || jj >= W) continue;
                size_t q = (size_t)ii * W + jj;
                if (g->coverage[q] <= 0.5f) {
                    kind = WS_PART_SILHOUETTE;
                    break;
                }
                if (!isfinite(g->depth[q]) || !isfinite(g->depth[p])) continue;
                if (g->depth[q] - g->depth[p] > WS_LINE_DEPTH_JUMP * g->depth[p]) {
                    kind = WS_PART_CONTOUR;
                    continue;
                }
                if (kind != WS_PART_MASK || fabsf(g->depth[q] - g->depth[p]) > WS_LINE_DEPTH_JUMP * g->depth[p] ||
                    cos_normals(g, p, q) >= crease)
                    continue;
                int ib = i - di[k], jb = j - dj[k], iq = ii + di[k], jq = jj + dj[k];
                if (ib < 0 || ib >= H || jb < 0 || jb >= W || iq < 0 || iq >= H || jq < 0 || jq >= W) continue;
                size_t pb = (size_t)ib * W + jb, qb = (size_t)iq * W + jq;
                if (g->coverage[pb] > 0.5f && g->coverage[qb] > 0.5f && cos_normals(g, p, pb) >= flat &&
                    cos_normals(g, q, qb) >= flat)
                    kind = WS_PART_CREASE;
            }
            part[p] = (uint8_t)kind;
        }
    for (size_t p = 0; p < n; p++) line[p] = (uint8_t)ws_part_is_line(part[p]);
    int rc = ws_skeleton_thin(line, W, H, st);
    if (!rc) {
        drop_specks(line, W, H, WS_LINE_MIN_SPECK, stack, mark);
        for (size_t p = 0; p < n; p++)
            if (!line[p] && ws_part_is_line(part[p])) part[p] = WS_PART_MASK;
    }
    free(line);
    free(mark);
    free(stack);
    return rc;
}
