/* splat.c: the tiled Gaussian splatting rasteriser (see splat.h).
 *
 * Forward: project every Gaussian (centre u, v and footprint sigma in
 * pixels), clip its cut-off box to the image, and bin it into 16 x 16 pixel
 * tiles with a counting sort, so each tile's list holds the Gaussians that
 * can touch it in index order. Tiles run in parallel; within a tile each
 * Gaussian visits the pixels of its box, so the cost follows the pixels
 * covered, and each pixel's transmittance T = prod (1 - w_k) is multiplied
 * up in index order; alpha = 1 - T.
 *
 * Backward: dalpha/dw_k = prod_{j != k} (1 - w_j), formed per pixel as
 * (prefix product before k) x (suffix product after k) without dividing by
 * 1 - w_k, which is 0 on an exact hit. A tile is done row by row: a forward
 * sweep over its list stores w and the prefix of every (Gaussian, pixel)
 * pair of the row, a backward sweep forms the suffix. Each (tile, Gaussian)
 * entry collects dL/d(u, v, sigma) from its tile's pixels; the entries are
 * then summed per Gaussian in tile order and carried to dL/dmu through the
 * projection. No sum depends on which thread ran a tile, so the result is
 * bit-identical for any thread count. Scratch: 16 pairs per list entry of
 * the longest tile list, per thread (so even the exact sum, where every
 * Gaussian is in every tile, needs only 256 bytes per Gaussian per thread). */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include "render/splat.h"
#include "nn/parallel.h"

#define TILE 16
#define PARALLEL_GAUSSIANS 16384
#define EXP_ZERO_SIGMAS 38.63 /* sqrt(2 * 746): beyond it w = exp(-r^2 / 2 sigma^2) == 0 */

typedef struct {
    double u, v, sigma;  /* centre in pixel indices (column, row): the image point less
                          * WS_PIXEL_CENTER, so pixel (i, j) is at offset (j - u, i - v);
                          * footprint in pixels */
    double c[3];         /* camera coordinates c = R mu + t */
    int x0, x1, y0, y1;  /* footprint box clipped to the image; empty (x0 > x1) if not drawn */
} projected;

struct ws_splat {
    int width, height, tiles_x, tiles_y, ntiles;
    int cap;              /* Gaussians the per-Gaussian buffers hold */
    projected *g;         /* cap */
    double *dproj;        /* cap x 3: dL/d(u, v, sigma) summed over tiles */
    size_t *tile_start;   /* ntiles + 1: tile k's entries are [tile_start[k], tile_start[k+1]) */
    size_t entry_cap;
    int *entry;           /* entry_cap: the Gaussian of each (tile, Gaussian) entry */
    double *dentry;       /* entry_cap x 3: that entry's dL/d(u, v, sigma) */
    int scratch_threads;
    size_t scratch_len;   /* (entry, pixel) pairs of one tile row, at most */
    double *scratch;      /* threads x scratch_len x 2: w and prefix product per pair */
    ws_camera cam;        /* of the last forward pass */
    double half_cutoff2;  /* 0.5 cutoff^2: w is 0 where (r / sigma)^2 / 2 exceeds it */
    int n;                /* Gaussians of the last forward pass; -1 before any */
};

void ws_splat_options_default(ws_splat_options *opt) {
    opt->cutoff = 4.0;
    opt->near = 1e-3;
    opt->far = NULL;
}

/* Grows an array to hold `count` items of `size` bytes (contents kept). */
static int grow(void **p, size_t count, size_t size, const char *what, ws_status *st) {
    size_t bytes = count * size;
    void *q = realloc(*p, bytes ? bytes : 1);
    if (!q) return ws_fail(st, WS_ENOMEM, "out of memory for %zu %s", count, what);
    *p = q;
    return WS_OK;
}

static int reserve_gaussians(ws_splat *s, int n, ws_status *st) {
    if (n <= s->cap) return WS_OK;
    int cap = s->cap * 2 > n ? s->cap * 2 : n;
    if (grow((void **)&s->g, (size_t)cap, sizeof *s->g, "projected Gaussians", st) ||
        grow((void **)&s->dproj, (size_t)cap * 3, sizeof *s->dproj, "Gaussian gradients", st))
        return st->code;
    s->cap = cap;
    return WS_OK;
}

static int reserve_entries(ws_splat *s, size_t n, ws_status *st) {
    if (n <= s->entry_cap) return WS_OK;
    size_t cap = s->entry_cap * 2 > n ? s->entry_cap * 2 : n;
    if (grow((void **)&s->entry, cap, sizeof *s->entry, "tile entries", st) ||
        grow((void **)&s->dentry, cap * 3, sizeof *s->dentry, "tile entry gradients", st))
        return st->code;
    s->entry_cap = cap;
    return WS_OK;
}

static int reserve_scratch(ws_splat *s, int threads, size_t len, ws_status *st) {
    if (threads <= s->scratch_threads && len <= s->scratch_len) return WS_OK;
    if (threads < s->scratch_threads) threads = s->scratch_threads;
    if (len < s->scratch_len) len = s->scratch_len;
    if (grow((void **)&s->scratch, (size_t)threads * len * 2, sizeof *s->scratch, "row scratch", st))
        return st->code;
    s->scratch_threads = threads;
    s->scratch_len = len;
    return WS_OK;
}

int ws_splat_create(ws_splat **out, int width, int height, ws_status *st) {
    *out = NULL;
    if (width <= 0 || height <= 0 || width > 1 << 15 || height > 1 << 15)
        return ws_fail(st, WS_EINPUT, "splat: image size %d x %d is out of range", width, height);
    ws_splat *s = ws_calloc(1, sizeof *s, "splat workspace", st);
    if (!s) return st->code;
    s->width = width;
    s->height = height;
    s->tiles_x = (width + TILE - 1) / TILE;
    s->tiles_y = (height + TILE - 1) / TILE;
    s->ntiles = s->tiles_x * s->tiles_y;
    s->n = -1;
    if (grow((void **)&s->tile_start, (size_t)s->ntiles + 1, sizeof *s->tile_start, "tiles", st) ||
        reserve_gaussians(s, 1024, st) || reserve_entries(s, 4096, st) ||
        reserve_scratch(s, omp_get_max_threads(), 1024, st)) {
        ws_splat_free(s);
        return st->code;
    }
    *out = s;
    return WS_OK;
}

void ws_splat_free(ws_splat *s) {
    if (!s) return;
    free(s->g);
    free(s->dproj);
    free(s->tile_start);
    free(s->entry);
    free(s->dentry);
    free(s->scratch);
    free(s);
}

/* Projects one Gaussian; a culled one (depth <= near, beyond the far limit
 * of its centre's pixel, or a projection that overflows) or one whose
 * cut-off box misses the image gets an empty box. */
static void project(const ws_camera *cam, const double mu[3], double radius, double cutoff,
                    double near, const float *far, projected *p) {
    ws_camera_to_cam(cam, mu, p->c);
    double u, v, d = ws_camera_project(cam, p->c, &u, &v);
    p->x0 = 1;
    p->x1 = 0;
    p->y0 = 1;
    p->y1 = 0;
    if (!(d > near)) return;
    if (far) {
        double j = floor(u), i = floor(v);
        if (j >= 0 && j < cam->width && i >= 0 && i < cam->height &&
            d > far[(size_t)i * cam->width + (size_t)j])
            return;
    }
    p->u = u - WS_PIXEL_CENTER;
    p->v = v - WS_PIXEL_CENTER;
    p->sigma = cam->focal * radius / d;
    if (!isfinite(p->u) || !isfinite(p->v) || !(p->sigma > 0) || !isfinite(p->sigma)) return;
    double reach = cutoff * p->sigma;
    double x0 = fmax(0, ceil(p->u - reach)), x1 = fmin(cam->width - 1, floor(p->u + reach));
    double y0 = fmax(0, ceil(p->v - reach)), y1 = fmin(cam->height - 1, floor(p->v + reach));
    if (x0 > x1 || y0 > y1) return;
    p->x0 = (int)x0;
    p->x1 = (int)x1;
    p->y0 = (int)y0;
    p->y1 = (int)y1;
}

/* Weight of Gaussian p at pixel (i, j) of its box, 0 beyond the cut-off,
 * and the scaled offsets qx = (j - u) / sigma, qy = (i - v) / sigma.
 * Offsets are scaled before squaring so that sigma far below a pixel cannot
 * overflow or turn an exact hit into 0/0. */
static inline double weight(const projected *p, int i, int j, double half_cutoff2, double *qx,
                            double *qy) {
    *qx = (j - p->u) / p->sigma;
    *qy = (i - p->v) / p->sigma;
    double e = 0.5 * (*qx * *qx + *qy * *qy);
    return e > half_cutoff2 ? 0.0 : exp(-e);
}

/* Counting sort of the drawn Gaussians into tiles, each tile's list in index
 * order; returns the longest list in *longest. */
static int bin_tiles(ws_splat *s, int n, int *longest, ws_status *st) {
    size_t *start = s->tile_start;
    memset(start, 0, ((size_t)s->ntiles + 1) * sizeof *start);
    for (int k = 0; k < n; k++) {
        const projected *p = &s->g[k];
        if (p->x0 > p->x1) continue;
        for (int ty = p->y0 / TILE; ty <= p->y1 / TILE; ty++)
            for (int tx = p->x0 / TILE; tx <= p->x1 / TILE; tx++) start[ty * s->tiles_x + tx + 1]++;
    }
    *longest = 0;
    for (int t = 0; t < s->ntiles; t++) {
        if ((int)start[t + 1] > *longest) *longest = (int)start[t + 1];
        start[t + 1] += start[t];
    }
    if (reserve_entries(s, start[s->ntiles], st)) return st->code;
    /* Fill: `start` is shifted by one tile while filling, so that afterwards
     * start[t] is again the beginning of tile t. */
    for (int t = s->ntiles; t > 0; t--) start[t] = start[t - 1];
    for (int k = 0; k < n; k++) {
        const projected *p = &s->g[k];
        if (p->x0 > p->x1) continue;
        for (int ty = p->y0 / TILE; ty <= p->y1 / TILE; ty++)
            for (int tx = p->x0 / TILE; tx <= p->x1 / TILE; tx++)
                s->entry[start[ty * s->tiles_x + tx + 1]++] = k;
    }
    return WS_OK;
}

/* forward: mu (n x 3), camera -> alpha (height x width) */
int ws_splat_forward(ws_splat *s, const ws_camera *cam, const double *mu, int n, double radius,
                     const ws_splat_options *opt, double *alpha, ws_status *st) {
    s->n = -1;
    if (cam->width != s->width || cam->height != s->height)
        return ws_fail(st, WS_EINTERNAL, "splat: camera is %d x %d but the workspace %d x %d",
                       cam->width, cam->height, s->width, s->height);
    if (n < 0 || !(radius > 0) || !isfinite(radius) || !(opt->cutoff > 0) ||
        !(opt->near >= 0) || !isfinite(opt->near))
        return ws_fail(st, WS_EINTERNAL, "splat: bad arguments (n %d, radius %g, cutoff %g, near %g)",
                       n, radius, opt->cutoff, opt->near);
    for (size_t k = 0; k < (size_t)n * 3; k++)
        if (!isfinite(mu[k]))
            return ws_fail(st, WS_ENUMERIC, "splat: Gaussian %zu has a non-finite centre", k / 3);
    if (reserve_gaussians(s, n, st)) return st->code;
    s->cam = *cam;
    /* exp(-e) is exactly 0 in double for e > 746 (below half the smallest
     * subnormal), so no cut-off beyond sqrt(2 * 746) = 38.6 sigmas changes a
     * bit: the exact sum (cutoff INFINITY) clips its boxes there too. */
    const double cutoff = fmin(opt->cutoff, EXP_ZERO_SIGMAS);
    s->half_cutoff2 = 0.5 * cutoff * cutoff;
    /* Per-Gaussian loops are cheap: a thread team pays only for many. */
    #pragma omp parallel for schedule(static) if (n >= PARALLEL_GAUSSIANS)
    for (int k = 0; k < n; k++)
        project(cam, mu + (size_t)k * 3, radius, cutoff, opt->near, opt->far, &s->g[k]);
    int longest;
    if (bin_tiles(s, n, &longest, st) || reserve_scratch(s, omp_get_max_threads(), (size_t)longest * TILE, st))
        return st->code;
    const int W = s->width, H = s->height;
    const double half_cutoff2 = s->half_cutoff2;
    /* Gaussian by Gaussian over each tile, so a Gaussian costs the pixels it
     * covers; every pixel still multiplies its factors in index order. */
    const size_t visits = s->tile_start[s->ntiles] * TILE * TILE; /* pixel visits at most */
    #pragma omp parallel for schedule(dynamic, 1) if (nn_fork(visits))
    for (int t = 0; t < s->ntiles; t++) {
        int i0 = (t / s->tiles_x) * TILE, j0 = (t % s->tiles_x) * TILE;
        int i1 = i0 + TILE < H ? i0 + TILE : H, j1 = j0 + TILE < W ? j0 + TILE : W;
        double T[TILE * TILE];
        for (int k = 0; k < TILE * TILE; k++) T[k] = 1.0;
        for (size_t e = s->tile_start[t]; e < s->tile_start[t + 1]; e++) {
            const projected *p = &s->g[s->entry[e]];
            int ia = p->y0 > i0 ? p->y0 : i0, ib = p->y1 < i1 - 1 ? p->y1 : i1 - 1;
            int ja = p->x0 > j0 ? p->x0 : j0, jb = p->x1 < j1 - 1 ? p->x1 : j1 - 1;
            for (int i = ia; i <= ib; i++)
                for (int j = ja; j <= jb; j++) {
                    double qx, qy;
                    T[(i - i0) * TILE + (j - j0)] *= 1.0 - weight(p, i, j, half_cutoff2, &qx, &qy);
                }
        }
        for (int i = i0; i < i1; i++)
            for (int j = j0; j < j1; j++) alpha[(size_t)i * W + j] = 1.0 - T[(i - i0) * TILE + (j - j0)];
    }
    s->n = n;
    return WS_OK;
}

/* Row i of a tile (columns j0 .. j1-1): each entry's share of dL/d(u, v,
 * sigma) from the row's pixels, added to s->dentry. With
 * dL/dw_k = dalpha prefix_k suffix_k, dw/du = w qx / sigma,
 * dw/dv = w qy / sigma, dw/dsigma = w (qx^2 + qy^2) / sigma.
 * Forward over the entries: store w and the prefix product of every pixel
 * an entry covers (wpre, in push order); backward over the entries: pop them
 * in reverse while the suffix product grows. */
static void row_backward(ws_splat *s, size_t first, size_t last, int i, int j0, int j1,
                         const double *dalpha_row, double *wpre) {
    double prefix[TILE], suffix[TILE], qx, qy;
    size_t m = 0;
    for (int j = j0; j < j1; j++) prefix[j - j0] = suffix[j - j0] = 1.0;
    for (size_t e = first; e < last; e++) {
        const projected *p = &s->g[s->entry[e]];
        if (i < p->y0 || i > p->y1) continue;
        int ja = p->x0 > j0 ? p->x0 : j0, jb = p->x1 < j1 - 1 ? p->x1 : j1 - 1;
        for (int j = ja; j <= jb; j++) {
            double w = weight(p, i, j, s->half_cutoff2, &qx, &qy);
            wpre[2 * m] = w;
            wpre[2 * m + 1] = prefix[j - j0];
            m++;
            prefix[j - j0] *= 1.0 - w;
        }
    }
    for (size_t e = last; e-- > first;) {
        const projected *p = &s->g[s->entry[e]];
        if (i < p->y0 || i > p->y1) continue;
        int ja = p->x0 > j0 ? p->x0 : j0, jb = p->x1 < j1 - 1 ? p->x1 : j1 - 1;
        double du = 0, dv = 0, dsigma = 0;
        for (int j = jb; j >= ja; j--) {
            m--;
            double w = wpre[2 * m];
            if (w == 0.0) continue; /* also keeps qx of a vanishing sigma out */
            double g = dalpha_row[j] * wpre[2 * m + 1] * suffix[j - j0] * w / p->sigma;
            qx = (j - p->u) / p->sigma;
            qy = (i - p->v) / p->sigma;
            du += g * qx;
            dv += g * qy;
            dsigma += g * (qx * qx + qy * qy);
            suffix[j - j0] *= 1.0 - w;
        }
        double *d = s->dentry + e * 3;
        d[0] += du;
        d[1] += dv;
        d[2] += dsigma;
    }
}

/* backward: dalpha (height x width) -> dmu (n x 3) */
int ws_splat_backward(ws_splat *s, const double *dalpha, double *dmu, ws_status *st) {
    if (s->n < 0) return ws_fail(st, WS_EINTERNAL, "splat: backward without a forward pass");
    const int W = s->width, H = s->height, n = s->n;
    for (size_t p = 0; p < (size_t)W * H; p++)
        if (!isfinite(dalpha[p]))
            return ws_fail(st, WS_ENUMERIC, "splat: dL/dalpha is not finite at pixel (%zu, %zu)",
                           p / W, p % W);
    /* The scratch was sized for the team of the forward pass; never more. */
    const int threads = omp_get_max_threads() < s->scratch_threads ? omp_get_max_threads()
                                                                  : s->scratch_threads;
    const size_t visits = s->tile_start[s->ntiles] * TILE * TILE; /* pixel visits at most */
    #pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (nn_fork(visits))
    for (int t = 0; t < s->ntiles; t++) {
        double *wpre = s->scratch + (size_t)omp_get_thread_num() * s->scratch_len * 2;
        size_t first = s->tile_start[t], last = s->tile_start[t + 1];
        memset(s->dentry + first * 3, 0, (last - first) * 3 * sizeof *s->dentry);
        int i0 = (t / s->tiles_x) * TILE, j0 = (t % s->tiles_x) * TILE;
        int i1 = i0 + TILE < H ? i0 + TILE : H, j1 = j0 + TILE < W ? j0 + TILE : W;
        for (int i = i0; i < i1; i++) {
            const double *row = dalpha + (size_t)i * W;
            int any = 0;
            for (int j = j0; j < j1; j++) any |= row[j] != 0.0;
            if (any) row_backward(s, first, last, i, j0, j1, row, wpre);
        }
    }
    /* Sum the entries per Gaussian in tile order (fixed, thread-independent). */
    memset(s->dproj, 0, (size_t)n * 3 * sizeof *s->dproj);
    for (size_t e = 0; e < s->tile_start[s->ntiles]; e++)
        for (int x = 0; x < 3; x++) s->dproj[(size_t)s->entry[e] * 3 + x] += s->dentry[e * 3 + x];
    /* Through the projection: u = W/2 + f cx / d, v = H/2 - f cy / d,
     * sigma = f r / d with d = -cz, so
     * du/dc = (f/d, 0, f cx/d^2), dv/dc = (0, -f/d, -f cy/d^2),
     * dsigma/dc = (0, 0, sigma/d); then dmu = R^T dc. */
    const ws_camera *cam = &s->cam;
    #pragma omp parallel for schedule(static) if (n >= PARALLEL_GAUSSIANS)
    for (int k = 0; k < n; k++) {
        const projected *p = &s->g[k];
        double *out = dmu + (size_t)k * 3;
        if (p->x0 > p->x1) {
            out[0] = out[1] = out[2] = 0.0;
            continue;
        }
        const double *g = s->dproj + (size_t)k * 3;
        double d = -p->c[2], f = cam->focal;
        double dc[3] = {g[0] * f / d, -g[1] * f / d,
                        (g[0] * f * p->c[0] - g[1] * f * p->c[1]) / (d * d) + g[2] * p->sigma / d};
        for (int x = 0; x < 3; x++)
            out[x] = cam->R[0][x] * dc[0] + cam->R[1][x] * dc[1] + cam->R[2][x] * dc[2];
    }
    return WS_OK;
}
