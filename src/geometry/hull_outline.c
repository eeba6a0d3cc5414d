/* hull_outline.c: the image-based visual hull of a view's pixels (see
 * hull_outline.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>
#include "geometry/hull_outline.h"
#include "render/distance.h"

/* Bounds sd, so that a full or an empty silhouette (distances INFINITY)
 * gives finite steps. */
#define SD_LIMIT 1e6f

int ws_hull_outline_init(ws_hull_outline *o, const ws_hull_view *views, int nviews, int tolerance,
                         const double lo[3], const double hi[3], ws_status *st) {
    *o = (ws_hull_outline){.views = views, .nviews = nviews, .tolerance = tolerance};
    if (nviews < 1 || tolerance < 0 || tolerance > 250 || !(lo[0] < hi[0] && lo[1] < hi[1] && lo[2] < hi[2]))
        return ws_fail(st, WS_EINTERNAL, "hull outline: %d views, tolerance %d, or an empty box", nviews, tolerance);
    memcpy(o->lo, lo, sizeof o->lo);
    memcpy(o->hi, hi, sizeof o->hi);
    o->sd = ws_calloc((size_t)nviews, sizeof *o->sd, "hull outline", st);
    if (!o->sd) return st->code;
    for (int k = 0; k < nviews; k++) {
        const ws_silhouette *s = views[k].sil;
        size_t n = (size_t)s->width * s->height;
        uint8_t *background = ws_malloc(n, "hull outline", st);
        float *to_background = background ? ws_malloc(n * sizeof(float), "hull outline", st) : NULL;
        o->sd[k] = to_background ? ws_malloc(n * sizeof(float), "hull outline", st) : NULL;
        int rc = o->sd[k] ? WS_OK : st->code;
        if (!rc) {
            for (size_t p = 0; p < n; p++) background[p] = !s->in[p];
            rc = ws_distance_map(background, s->width, s->height, to_background, st);
        }
        for (size_t p = 0; !rc && p < n; p++) {
            float v = (float)((s->in[p] ? 0.5 - to_background[p] : s->distance[p] - 0.5) + s->edge_inset);
            o->sd[k][p] = v > SD_LIMIT ? SD_LIMIT : v < -SD_LIMIT ? -SD_LIMIT : v;
        }
        free(background);
        free(to_background);
        if (rc) {
            ws_hull_outline_free(o);
            return rc;
        }
    }
    return WS_OK;
}

void ws_hull_outline_free(ws_hull_outline *o) {
    for (int k = 0; o->sd && k < o->nviews; k++) free(o->sd[k]);
    free(o->sd);
    o->sd = NULL;
}

void ws_hull_outline_box(const ws_hull *h, double lo[3], double hi[3]) {
    for (int a = 0; a < 3; a++) {
        lo[a] = h->origin[a];
        hi[a] = h->origin[a] + h->n[a] * h->voxel;
    }
}

/* sd of map (W x H) at image point (u, v), bilinear between pixel centres
 * (clamped to the outermost ones). */
static double sd_at(const float *sd, int W, int H, double u, double v) {
    double x = fmin(fmax(u - WS_PIXEL_CENTER, 0), W - 1), y = fmin(fmax(v - WS_PIXEL_CENTER, 0), H - 1);
    int j = (int)x < W - 1 ? (int)x : W - 2 < 0 ? 0 : W - 2, i = (int)y < H - 1 ? (int)y : H - 2 < 0 ? 0 : H - 2;
    int j1 = j + 1 < W ? j + 1 : j, i1 = i + 1 < H ? i + 1 : i;
    double fx = x - j, fy = y - i;
    double top = sd[(size_t)i * W + j] * (1 - fx) + sd[(size_t)i * W + j1] * fx;
    double bottom = sd[(size_t)i1 * W + j] * (1 - fx) + sd[(size_t)i1 * W + j1] * fx;
    return top * (1 - fy) + bottom * fy;
}

/* How far view k sees the ray's point at t outside (pixels; <= 0: inside
 * or no say), and the speed of its projection along the ray (pixels per
 * unit t). a, b: the ray in view k's camera space, a + t b. */
static double outside_by(const ws_hull_outline *o, int k, const double a[3], const double b[3], double t,
                         double *speed) {
    const ws_camera *cam = o->views[k].cam;
    const ws_silhouette *s = o->views[k].sil;
    double c[3] = {a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2]}, u, v;
    double d = ws_camera_project(cam, c, &u, &v);
    *speed = 0;
    if (!(d > 1e-9)) return -1; /* behind the camera: no say */
    /* d(u)/dt = f (b0 d + c0 b2) / d^2, d(v)/dt = -f (b1 d + c1 b2) / d^2 (d = -c2, dd/dt = -b2) */
    double du = cam->focal * (b[0] * d + c[0] * b[2]) / (d * d), dv = -cam->focal * (b[1] * d + c[1] * b[2]) / (d * d);
    *speed = sqrt(du * du + dv * dv);
    const double W = cam->width, H = cam->height;
    double cu = u < 0 ? 0 : u > W ? W : u, cv = v < 0 ? 0 : v > H ? H : v;
    if (cu != u || cv != v) return s->touches_border ? -1 : hypot(u - cu, v - cv) + 0.5;
    return sd_at(o->sd[k], cam->width, cam->height, u, v);
}

/* The m-th largest of x[0..n) (m <= n), by a running list of the m
 * largest. */
static double mth_largest(const double *x, int n, int m, double *top) {
    int have = 0;
    for (int k = 0; k < n; k++) {
        if (have == m && x[k] <= top[m - 1]) continue;
        int at = have < m ? have++ : m - 1;
        while (at > 0 && top[at - 1] < x[k]) {
            top[at] = top[at - 1];
            at--;
        }
        top[at] = x[k];
    }
    return top[m - 1];
}

/* The ray's parameter range [*t0, *t1] inside the box (slabs); 0 when it
 * misses the box. */
static int box_range(const double lo[3], const double hi[3], const double p[3], const double w[3], double *t0,
                     double *t1) {
    double a = 0, b = INFINITY;
    for (int x = 0; x < 3; x++) {
        if (w[x] == 0) {
            if (p[x] < lo[x] || p[x] > hi[x]) return 0;
            continue;
        }
        double e = (lo[x] - p[x]) / w[x], f = (hi[x] - p[x]) / w[x];
        a = fmax(a, fmin(e, f));
        b = fmin(b, fmax(e, f));
    }
    *t0 = a;
    *t1 = b;
    return a < b;
}

static int covers(const ws_hull_outline *o, const ws_camera *cam, int i, int j, double near, double far,
                  double (*ab)[6], double *gap, double *top) {
    double D[3], w[3], p[3], t0, t1;
    ws_camera_pixel_ray(cam, i, j, D);
    for (int x = 0; x < 3; x++) w[x] = cam->R[0][x] * D[0] + cam->R[1][x] * D[1] + cam->R[2][x] * D[2];
    ws_camera_position(cam, p);
    if (!box_range(o->lo, o->hi, p, w, &t0, &t1)) return 0;
    /* D's z is -1: t is the depth, which the range bounds */
    t0 = fmax(t0, near);
    t1 = fmin(t1, far);
    for (int k = 0; k < o->nviews; k++) {
        const ws_camera *c = o->views[k].cam;
        ws_camera_to_cam(c, p, ab[k]);
        for (int x = 0; x < 3; x++) ab[k][3 + x] = c->R[x][0] * w[0] + c->R[x][1] * w[1] + c->R[x][2] * w[2];
    }
    const int m = o->tolerance + 1;
    double t = t0;
    for (int step = 0; step < WS_OUTLINE_MAX_STEPS && t <= t1; step++) {
        int outside = 0;
        double fastest = 0;
        for (int k = 0; k < o->nviews; k++) {
            double speed, s = outside_by(o, k, ab[k], ab[k] + 3, t, &speed);
            fastest = fmax(fastest, speed);
            outside += s > 0;
            gap[k] = s > 0 ? s / (M_SQRT2 * fmax(speed, 1e-12)) : 0;
        }
        if (outside < m) return 1;
        double reach = mth_largest(gap, o->nviews, m, top);
        t += fmax(WS_OUTLINE_STEP_SHARE * reach, WS_OUTLINE_MIN_STEP_PX / fmax(fastest, 1e-12));
    }
    return 0;
}

int ws_hull_outline_cover(const ws_hull_outline *o, const ws_camera *cam, const uint8_t *band, const float *near,
                          const float *far, uint8_t *covered, ws_status *st) {
    const int W = cam->width, H = cam->height, threads = omp_get_max_threads();
    /* per thread: the ray in every view's camera space, the views' gaps and the running list of the largest */
    const size_t per = (size_t)o->nviews * 7 + (size_t)o->tolerance + 1;
    double *scratch = ws_malloc((size_t)threads * per * sizeof *scratch, "hull outline", st);
    if (!scratch) return st->code;
#pragma omp parallel for schedule(dynamic, 4)
    for (int i = 0; i < H; i++) {
        double *mine = scratch + (size_t)omp_get_thread_num() * per;
        for (int j = 0; j < W; j++) {
            size_t p = (size_t)i * W + j;
            if (band[p])
                covered[p] = (uint8_t)covers(o, cam, i, j, near ? near[p] : 0, far ? far[p] : INFINITY,
                                             (double(*)[6])mine, mine + (size_t)o->nviews * 6,
                                             mine + (size_t)o->nviews * 7);
        }
    }
    free(scratch);
    return WS_OK;
}
