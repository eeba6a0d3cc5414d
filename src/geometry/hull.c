/* hull.c: voxel carving (see hull.h). */
#include <math.h>
#include <stdlib.h>
#include <omp.h>
#include <string.h>
#include "geometry/hull.h"

#define TIGHT_REACH 0.5  /* the tight test's share of the ball's projected radius */

/* At most 250: the per-voxel counter is a byte that counts to tolerance + 2
 * (ws_hull_carve refuses more); 250 of 5,000 views and more is still 5%
 * or less. */
int ws_hull_default_tolerance(int nviews) { return nviews / 20 < 250 ? nviews / 20 : 250; }

void ws_hull_voxel_center(const ws_hull *h, int x, int y, int z, double p[3]) {
    p[0] = h->origin[0] + (x + 0.5) * h->voxel;
    p[1] = h->origin[1] + (y + 0.5) * h->voxel;
    p[2] = h->origin[2] + (z + 0.5) * h->voxel;
}

/* Whether view v sees the ball (p, rho) outside its silhouette (hull.h;
 * tight: the tight test). */
static int sees_outside(const ws_hull_view *v, const double p[3], double rho, int tight) {
    const ws_camera *cam = v->cam;
    const ws_silhouette *s = v->sil;
    double c[3], u, w;
    ws_camera_to_cam(cam, p, c);
    double d = ws_camera_project(cam, c, &u, &w);
    if (!(d > 2 * rho)) return 0; /* the ball reaches the camera plane: no say */
    double reach = (tight ? TIGHT_REACH : 1.0) * cam->focal * rho / (d - rho);
    const double width = cam->width, height = cam->height; /* u, w clamped to the frame: */
    double cu = u < 0 ? 0 : u > width ? width : u, cv = w < 0 ? 0 : w > height ? height : w;
    if (cu != u || cv != w) {
        if (s->touches_border) return 0;
        return hypot(u - cu, w - cv) > reach;
    }
    int j = (int)u < cam->width ? (int)u : cam->width - 1, i = (int)w < cam->height ? (int)w : cam->height - 1;
    return s->distance[(size_t)i * cam->width + j] > reach + (tight ? 0.0 : WS_SILHOUETTE_PIXEL_SLACK);
}

/* Counts, for every voxel of h's grid, the views that see it outside, up
 * to tolerance + 2 (enough to tell the hull and the hull less one view). */
static void count_outside(const ws_hull_view *views, int nviews, ws_hull *h) {
    const double rho = h->voxel * sqrt(3.0) / 2;
    const int cap = h->tolerance + 2;
    long kept = 0;
    #pragma omp parallel for schedule(dynamic, 1) reduction(+ : kept)
    for (int z = 0; z < h->n[2]; z++)
        for (int y = 0; y < h->n[1]; y++)
            for (int x = 0; x < h->n[0]; x++) {
                double p[3];
                ws_hull_voxel_center(h, x, y, z, p);
                int count = 0;
                for (int k = 0; k < nviews && count < cap; k++)
                    count += sees_outside(&views[k], p, rho, h->tight);
                size_t at = ws_hull_index(h, x, y, z);
                h->outside[at] = (uint8_t)count;
                kept += count <= h->tolerance;
            }
    h->kept = kept;
}

static int carve_grid(const ws_hull_view *views, int nviews, const double origin[3], double voxel,
                      const int n[3], int tolerance, int tight, ws_hull *h, ws_status *st) {
    ws_hull_free(h);
    h->tight = tight;
    memcpy(h->n, n, sizeof h->n);
    memcpy(h->origin, origin, sizeof h->origin);
    h->voxel = voxel;
    h->tolerance = tolerance;
    h->outside = ws_malloc((size_t)n[0] * n[1] * n[2], "a voxel grid", st);
    if (!h->outside) return st->code;
    count_outside(views, nviews, h);
    return WS_OK;
}

int ws_hull_carve(const ws_hull_view *views, int nviews, const double center[3], int resolution,
                  int tolerance, int tight, ws_hull *h, ws_status *st) {
    *h = (ws_hull){0};
    if (nviews < 1 || resolution < 2 || resolution > 1024 || tolerance < 0 || tolerance > 250)
        return ws_fail(st, WS_EINTERNAL, "hull: %d views, resolution %d, tolerance %d", nviews,
                       resolution, tolerance);
    double half = 0;
    for (int k = 0; k < nviews; k++) {
        double pos[3];
        ws_camera_position(views[k].cam, pos);
        double dist = sqrt((pos[0] - center[0]) * (pos[0] - center[0]) +
                           (pos[1] - center[1]) * (pos[1] - center[1]) +
                           (pos[2] - center[2]) * (pos[2] - center[2]));
        const ws_camera *c = views[k].cam;
        half = fmax(half, dist * 0.5 * fmax(c->width, c->height) / c->focal * sqrt(2.0));
    }
    if (!(half > 0) || !isfinite(half))
        return ws_fail(st, WS_EINPUT, "hull: the cameras sit on the scene centre");
    const int coarse[3] = {WS_HULL_COARSE, WS_HULL_COARSE, WS_HULL_COARSE};
    double origin[3] = {center[0] - half, center[1] - half, center[2] - half};
    if (carve_grid(views, nviews, origin, 2 * half / WS_HULL_COARSE, coarse, tolerance, tight, h, st))
        return st->code;
    if (h->kept == 0) return WS_OK; /* nothing to refine: an empty hull */
    int lo[3] = {coarse[0], coarse[1], coarse[2]}, hi[3] = {-1, -1, -1};
    for (int z = 0; z < coarse[2]; z++)
        for (int y = 0; y < coarse[1]; y++)
            for (int x = 0; x < coarse[0]; x++) {
                if (!ws_hull_in(h, ws_hull_index(h, x, y, z))) continue;
                int v[3] = {x, y, z};
                for (int a = 0; a < 3; a++) {
                    if (v[a] < lo[a]) lo[a] = v[a];
                    if (v[a] > hi[a]) hi[a] = v[a];
                }
            }
    double box_lo[3], extent[3], longest = 0, cvox = h->voxel;
    for (int a = 0; a < 3; a++) {
        box_lo[a] = h->origin[a] + (lo[a] - 1) * cvox;
        extent[a] = (hi[a] - lo[a] + 3) * cvox;
        longest = fmax(longest, extent[a]);
    }
    double voxel = longest / resolution;
    int n[3];
    for (int a = 0; a < 3; a++) n[a] = (int)ceil(extent[a] / voxel - 1e-9);
    return carve_grid(views, nviews, box_lo, voxel, n, tolerance, tight, h, st);
}

void ws_hull_free(ws_hull *h) {
    free(h->outside);
    h->outside = NULL;
    h->kept = 0;
}

/* The hull drawn into view `self`'s image: less that view where the hull
 * was carved from `views` (voxels seen outside by at most tolerance views
 * other than it), else whole (a view it has not seen). Only the pixels set in
 * `todo` (H x W) are drawn, each at most once: drawing clears it, so a
 * solid hull's many voxels behind the first skip their pixels' disc test.
 * Returns the pixels drawn. */
static long project_others(const ws_hull_view *views, int self, int carved, const ws_hull *h, uint8_t *todo) {
    const ws_hull_view *v = &views[self];
    const ws_camera *cam = v->cam;
    const int W = cam->width, H = cam->height;
    const double rho = h->voxel * sqrt(3.0) / 2, inscribed = h->voxel / 2;
    long drawn = 0;
    for (int z = 0; z < h->n[2]; z++)
        for (int y = 0; y < h->n[1]; y++)
            for (int x = 0; x < h->n[0]; x++) {
                int count = h->outside[ws_hull_index(h, x, y, z)];
                if (count > h->tolerance + carved) continue;
                double p[3], c[3], u, w;
                ws_hull_voxel_center(h, x, y, z, p);
                if (count > h->tolerance && !sees_outside(v, p, rho, h->tight)) continue;
                ws_camera_to_cam(cam, p, c);
                double d = ws_camera_project(cam, c, &u, &w);
                if (!(d > inscribed)) continue;
                double r = cam->focal * inscribed / d;
                int j0 = (int)floor(u - r), j1 = (int)floor(u + r), i0 = (int)floor(w - r), i1 = (int)floor(w + r);
                const int ju = (int)floor(u), iw = (int)floor(w);
                for (int i = i0 > 0 ? i0 : 0; i <= i1 && i < H; i++)
                    for (int j = j0 > 0 ? j0 : 0; j <= j1 && j < W; j++) {
                        uint8_t *t = &todo[(size_t)i * W + j];
                        if (!*t) continue;
                        double du = j + WS_PIXEL_CENTER - u, dv = i + WS_PIXEL_CENTER - w;
                        if ((j == ju && i == iw) || du * du + dv * dv <= r * r) {
                            *t = 0;
                            drawn++;
                        }
                    }
            }
    return drawn;
}

int ws_hull_agreement(const ws_hull_view *views, int nviews, int carved, const ws_hull *h,
                      double *agreement, ws_status *st) {
    int W = 0, H = 0;
    for (int k = 0; k < nviews; k++) {
        W = W > views[k].cam->width ? W : views[k].cam->width;
        H = H > views[k].cam->height ? H : views[k].cam->height;
    }
    int threads = 1;
    #pragma omp parallel
    #pragma omp single
    threads = omp_get_num_threads();
    uint8_t *drawn = ws_malloc((size_t)threads * W * H, "hull projections", st);
    if (!drawn) return st->code;
    #pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < nviews; k++) {
        uint8_t *mine = drawn + (size_t)omp_get_thread_num() * W * H;
        const ws_silhouette *s = views[k].sil;
        /* The IoU needs the projection only inside the silhouette, or
         * anywhere for an empty one. */
        const size_t npix = (size_t)s->width * s->height;
        if (s->area)
            memcpy(mine, s->in, npix);
        else
            memset(mine, 1, npix);
        long both = project_others(views, k, carved != 0, h, mine);
        agreement[k] = s->area ? (double)both / s->area : (both ? 0.0 : 1.0);
    }
    free(drawn);
    return WS_OK;
}
