/* augment.c: perspective warp + resized crop and its transpose (augment.h).
 *
 * The forward pass is two linear resamplings:
 *   warp:   crop region of the perspective-warped image, C x ch x cw, each
 *           pixel 4 taps of the source (weights already multiplied by
 *           torchvision's fill mask);
 *   resize: C x ch x cw -> C x H x W, bilinear, align_corners=False.
 * Both stencils are rebuilt from the parameters at every call (a few
 * divisions per pixel), so forward and backward need no shared state. */
#include <math.h>
#include <stdlib.h>
#include "render/augment.h"
#include "nn/parallel.h"

struct ws_aug_workspace {
    int width, height, channels;
    float *warped;  /* channels x crop pixels */
    int *tap;       /* crop pixels x 4: source pixel index of each tap */
    float *weight;  /* crop pixels x 4: tap weight, 0 for a tap outside */
    int *row_tap;   /* height x 2: crop rows read by each output row */
    float *row_frac;/* height: weight of the second row */
    int *col_tap;   /* width x 2 */
    float *col_frac;/* width */
};

/* Solves the 8 x 8 system a x = b by Gaussian elimination with partial
 * pivoting; returns 0 when it is (numerically) singular. */
static int solve8(double a[8][8], double b[8], double x[8]) {
    for (int k = 0; k < 8; k++) {
        int piv = k;
        for (int i = k + 1; i < 8; i++)
            if (fabs(a[i][k]) > fabs(a[piv][k])) piv = i;
        if (!(fabs(a[piv][k]) > 1e-9)) return 0;
        if (piv != k) {
            for (int j = 0; j < 8; j++) {
                double t = a[k][j];
                a[k][j] = a[piv][j];
                a[piv][j] = t;
            }
            double t = b[k];
            b[k] = b[piv];
            b[piv] = t;
        }
        for (int i = k + 1; i < 8; i++) {
            double f = a[i][k] / a[k][k];
            for (int j = k; j < 8; j++) a[i][j] -= f * a[k][j];
            b[i] -= f * b[k];
        }
    }
    for (int k = 7; k >= 0; k--) {
        double s = b[k];
        for (int j = k + 1; j < 8; j++) s -= a[k][j] * x[j];
        x[k] = s / a[k][k];
    }
    return 1;
}

int ws_aug_params_init(ws_aug_params *p, int width, int height, const int corner[4][2],
                       int crop_top, int crop_left, int crop_height, int crop_width,
                       ws_status *st) {
    if (width < 1 || height < 1)
        return ws_fail(st, WS_EINPUT, "augment: image size %dx%d is empty", width, height);
    if (crop_height < 1 || crop_width < 1 || crop_top < 0 || crop_left < 0 ||
        crop_top + crop_height > height || crop_left + crop_width > width)
        return ws_fail(st, WS_EINPUT,
                       "augment: crop box (top %d, left %d, %dx%d) is not inside the %dx%d image",
                       crop_top, crop_left, crop_width, crop_height, width, height);
    p->width = width;
    p->height = height;
    p->crop_top = crop_top;
    p->crop_left = crop_left;
    p->crop_height = crop_height;
    p->crop_width = crop_width;
    /* The homography takes each end point (where a corner goes) back to its
     * start point (the corner), torchvision's _get_perspective_coeffs; it is
     * solved in double where torch uses float32 least squares. */
    const double start[4][2] = {{0, 0}, {width - 1, 0}, {width - 1, height - 1}, {0, height - 1}};
    double a[8][8], b[8];
    for (int k = 0; k < 4; k++) {
        double ex = corner[k][0], ey = corner[k][1], sx = start[k][0], sy = start[k][1];
        p->corner[k][0] = corner[k][0];
        p->corner[k][1] = corner[k][1];
        const double rx[8] = {ex, ey, 1, 0, 0, 0, -sx * ex, -sx * ey};
        const double ry[8] = {0, 0, 0, ex, ey, 1, -sy * ex, -sy * ey};
        for (int j = 0; j < 8; j++) {
            a[2 * k][j] = rx[j];
            a[2 * k + 1][j] = ry[j];
        }
        b[2 * k] = sx;
        b[2 * k + 1] = sy;
    }
    if (!solve8(a, b, p->homography))
        return ws_fail(st, WS_EINPUT, "augment: corners (%d,%d) (%d,%d) (%d,%d) (%d,%d) are degenerate",
                       corner[0][0], corner[0][1], corner[1][0], corner[1][1], corner[2][0],
                       corner[2][1], corner[3][0], corner[3][1]);
    return WS_OK;
}

/* Uniform integer in [lo, hi), torch.randint(lo, hi). */
static int randint(ws_rng *rng, int lo, int hi) { return lo + (int)ws_rng_below(rng, (uint64_t)(hi - lo)); }

int ws_aug_sample(ws_aug_params *p, ws_rng *rng, int width, int height, ws_status *st) {
    if (width < 2 || height < 2)
        return ws_fail(st, WS_EINPUT, "augment: image size %dx%d is too small (needs 2x2)", width,
                       height);
    /* RandomPerspective.get_params: dx, dy = how far a corner may move in. */
    int dx = (int)(WS_AUG_DISTORTION * (width / 2));
    int dy = (int)(WS_AUG_DISTORTION * (height / 2));
    /* RandomResizedCrop.get_params with scale (0.8, 0.8), ratio (1, 1): torch
     * draws the scale as a float32, and Python's round() is half-to-even
     * (lrint under the default rounding mode). Every one of its 10 attempts
     * is the same square, so one attempt and then its fallback suffice. */
    int side = (int)lrint(sqrt((double)width * height * (double)(float)WS_AUG_CROP_SCALE));
    /* In a tiny image the corners can fall on a line (no homography): such
     * a draw is drawn again, as a fit must not stop on a random draw. */
    for (int attempt = 0;; attempt++) {
        int corner[4][2];
        corner[0][0] = randint(rng, 0, dx + 1);
        corner[0][1] = randint(rng, 0, dy + 1);
        corner[1][0] = randint(rng, width - dx - 1, width);
        corner[1][1] = randint(rng, 0, dy + 1);
        corner[2][0] = randint(rng, width - dx - 1, width);
        corner[2][1] = randint(rng, height - dy - 1, height);
        corner[3][0] = randint(rng, 0, dx + 1);
        corner[3][1] = randint(rng, height - dy - 1, height);
        int top, left, ch, cw;
        if (side > 0 && side <= width && side <= height) {
            ch = cw = side;
            top = randint(rng, 0, height - side + 1);
            left = randint(rng, 0, width - side + 1);
        } else {
            ch = cw = width < height ? width : height;
            top = (height - ch) / 2;
            left = (width - cw) / 2;
        }
        int rc = ws_aug_params_init(p, width, height, (const int(*)[2])corner, top, left, ch, cw, st);
        if (rc == WS_OK || attempt == 99) return rc;
    }
}

int ws_aug_workspace_create(ws_aug_workspace **out, int width, int height, int channels,
                            ws_status *st) {
    *out = NULL;
    if (width < 1 || height < 1 || channels < 1)
        return ws_fail(st, WS_EINTERNAL, "augment: workspace for an empty %d-channel %dx%d image",
                       channels, width, height);
    ws_aug_workspace *ws = ws_calloc(1, sizeof *ws, "augment workspace", st);
    if (!ws) return st->code;
    size_t n = (size_t)width * height;
    ws->width = width;
    ws->height = height;
    ws->channels = channels;
    if (!(ws->warped = ws_malloc(n * channels * sizeof(float), "augment workspace", st)) ||
        !(ws->tap = ws_malloc(n * 4 * sizeof(int), "augment workspace", st)) ||
        !(ws->weight = ws_malloc(n * 4 * sizeof(float), "augment workspace", st)) ||
        !(ws->row_tap = ws_malloc((size_t)height * 2 * sizeof(int), "augment workspace", st)) ||
        !(ws->row_frac = ws_malloc((size_t)height * sizeof(float), "augment workspace", st)) ||
        !(ws->col_tap = ws_malloc((size_t)width * 2 * sizeof(int), "augment workspace", st)) ||
        !(ws->col_frac = ws_malloc((size_t)width * sizeof(float), "augment workspace", st))) {
        ws_aug_workspace_free(ws);
        return st->code;
    }
    *out = ws;
    return WS_OK;
}

void ws_aug_workspace_free(ws_aug_workspace *ws) {
    if (!ws) return;
    free(ws->warped);
    free(ws->tap);
    free(ws->weight);
    free(ws->row_tap);
    free(ws->row_frac);
    free(ws->col_tap);
    free(ws->col_frac);
    free(ws);
}

/* The warp stencil of every pixel of the crop box: grid_sample's bilinear
 * taps at the homography of the pixel centre, times torchvision's fill mask
 * (the in-bounds share of the taps). */
static void build_warp(const ws_aug_params *p, ws_aug_workspace *ws) {
    const double *h = p->homography;
    int W = p->width, H = p->height, cw = p->crop_width;
#pragma omp parallel for if (nn_fork((size_t)p->crop_height * cw))
    for (int r = 0; r < p->crop_height; r++) {
        double y = p->crop_top + r + 0.5;
        for (int c = 0; c < cw; c++) {
            double x = p->crop_left + c + 0.5;
            int *tap = ws->tap + ((size_t)r * cw + c) * 4;
            float *wt = ws->weight + ((size_t)r * cw + c) * 4;
            for (int k = 0; k < 4; k++) {
                tap[k] = 0;
                wt[k] = 0;
            }
            double den = h[6] * x + h[7] * y + 1;
            double sx = (h[0] * x + h[1] * y + h[2]) / den - 0.5;
            double sy = (h[3] * x + h[4] * y + h[5]) / den - 0.5;
            /* Also false for NaN (den = 0): such a pixel reads nothing. */
            if (!(den > 0 && sx > -1 && sx < W && sy > -1 && sy < H)) continue;
            int x0 = (int)floor(sx), y0 = (int)floor(sy);
            double fx = sx - x0, fy = sy - y0;
            double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
            int in[4] = {x0 >= 0 && y0 >= 0, x0 + 1 < W && y0 >= 0, x0 >= 0 && y0 + 1 < H,
                         x0 + 1 < W && y0 + 1 < H};
            double mask = 0;
            for (int k = 0; k < 4; k++)
                if (in[k]) mask += w[k];
            for (int k = 0; k < 4; k++) {
                if (!in[k]) continue;
                tap[k] = (y0 + k / 2) * W + x0 + k % 2;
                wt[k] = (float)(w[k] * mask);
            }
        }
    }
}

/* Bilinear taps of an upsampling n_in -> n_out with align_corners=False:
 * source = (dst + 0.5) * n_in / n_out - 0.5, clamped at 0 (torch's
 * area_pixel_compute_source_index), second tap clamped at n_in - 1. */
static void build_resize(int n_in, int n_out, int *tap, float *frac) {
    double scale = (double)n_in / n_out;
    for (int i = 0; i < n_out; i++) {
        double s = (i + 0.5) * scale - 0.5;
        if (s < 0) s = 0;
        int i0 = (int)s;
        tap[2 * i] = i0;
        tap[2 * i + 1] = i0 < n_in - 1 ? i0 + 1 : i0;
        frac[i] = (float)(s - i0);
    }
}

static int prepare(const ws_aug_params *p, int C, int H, int W, ws_aug_workspace *ws,
                   ws_status *st) {
    if (H != p->height || W != p->width || W > ws->width || H > ws->height || C < 1 ||
        C > ws->channels)
        return ws_fail(st, WS_EINTERNAL,
                       "augment: %d-channel %dx%d image does not fit the %dx%d transform or the "
                       "%d-channel %dx%d workspace",
                       C, W, H, p->width, p->height, ws->channels, ws->width, ws->height);
    build_warp(p, ws);
    build_resize(p->crop_height, H, ws->row_tap, ws->row_frac);
    build_resize(p->crop_width, W, ws->col_tap, ws->col_frac);
    return WS_OK;
}

int ws_aug_forward(const ws_aug_params *p, const float *in, int C, int H, int W, float *out,
                   ws_aug_workspace *ws, ws_status *st) {
    if (prepare(p, C, H, W, ws, st)) return st->code;
    int ch = p->crop_height, cw = p->crop_width;
    size_t hw = (size_t)H * W, crop = (size_t)ch * cw;
#pragma omp parallel for collapse(2) if (nn_fork((size_t)C * crop))
    for (int c = 0; c < C; c++)
        for (int r = 0; r < ch; r++) {
            const float *src = in + c * hw;
            float *dst = ws->warped + c * crop + (size_t)r * cw;
            const int *tap = ws->tap + (size_t)r * cw * 4;
            const float *wt = ws->weight + (size_t)r * cw * 4;
            for (int j = 0; j < cw; j++, tap += 4, wt += 4)
                dst[j] = wt[0] * src[tap[0]] + wt[1] * src[tap[1]] + wt[2] * src[tap[2]] +
                         wt[3] * src[tap[3]];
        }
#pragma omp parallel for collapse(2) if (nn_fork((size_t)C * hw))
    for (int c = 0; c < C; c++)
        for (int i = 0; i < H; i++) {
            const float *r0 = ws->warped + c * crop + (size_t)ws->row_tap[2 * i] * cw;
            const float *r1 = ws->warped + c * crop + (size_t)ws->row_tap[2 * i + 1] * cw;
            float fy = ws->row_frac[i];
            float *dst = out + c * hw + (size_t)i * W;
            for (int j = 0; j < W; j++) {
                int x0 = ws->col_tap[2 * j], x1 = ws->col_tap[2 * j + 1];
                float fx = ws->col_frac[j];
                dst[j] = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x1]) +
                         fy * ((1 - fx) * r1[x0] + fx * r1[x1]);
            }
        }
    return WS_OK;
}

int ws_aug_backward(const ws_aug_params *p, const float *dout, int C, int H, int W, float *din,
                    ws_aug_workspace *ws, ws_status *st) {
    if (prepare(p, C, H, W, ws, st)) return st->code;
    int ch = p->crop_height, cw = p->crop_width;
    size_t hw = (size_t)H * W, crop = (size_t)ch * cw;
    /* Each channel is one thread's scatter in pixel order: the same sums in
     * the same order whatever the thread count. */
#pragma omp parallel for if (nn_fork((size_t)C * crop))
    for (int c = 0; c < C; c++) {
        float *dwarp = ws->warped + c * crop;
        for (size_t k = 0; k < crop; k++) dwarp[k] = 0;
        for (int i = 0; i < H; i++) {
            float *r0 = dwarp + (size_t)ws->row_tap[2 * i] * cw;
            float *r1 = dwarp + (size_t)ws->row_tap[2 * i + 1] * cw;
            float fy = ws->row_frac[i];
            const float *g = dout + c * hw + (size_t)i * W;
            for (int j = 0; j < W; j++) {
                int x0 = ws->col_tap[2 * j], x1 = ws->col_tap[2 * j + 1];
                float fx = ws->col_frac[j];
                r0[x0] += (1 - fy) * (1 - fx) * g[j];
                r0[x1] += (1 - fy) * fx * g[j];
                r1[x0] += fy * (1 - fx) * g[j];
                r1[x1] += fy * fx * g[j];
            }
        }
        float *dst = din + c * hw;
        for (size_t k = 0; k < hw; k++) dst[k] = 0;
        const int *tap = ws->tap;
        const float *wt = ws->weight;
        for (size_t k = 0; k < crop; k++, tap += 4, wt += 4)
            for (int t = 0; t < 4; t++) dst[tap[t]] += wt[t] * dwarp[k];
    }
    return WS_OK;
}
