/* respawn.c: moving idle curves (see respawn.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "fit/respawn.h"
#include "render/distance.h"
#include "geometry/silhouette.h"
#include "geometry/surface.h"
#include "objective/view_targets.h"

#define DIRECTION_RADIUS 3 /* px: the edge pixels that give an edge's direction */
#define END_SLOPE 3.0      /* a stroke's end is searched this many times its image offset in depth */

struct ws_respawn {
    const ws_split *train;
    int W, H;
    const ws_silhouette *sil; /* one per training view, borrowed */
    const ws_scene_hull *hull; /* borrowed */
    double length;            /* of a stroke on the hull, the longest on an edge */
    float *edge_distance;     /* views x H x W: pixels to the nearest edge pixel */
    int *edge_start;          /* views + 1: view k's edge pixels are [edge_start[k], edge_start[k + 1]) */
    int *edge_pixel;          /* i W + j of every edge pixel, view after view */
    float *uncovered;         /* per edge pixel: its distance to the sketch */
    uint8_t *mark;            /* H x W scratch: projected centres */
    float *sketch_distance;   /* H x W scratch */
};

/* The edge pixels and edge distance maps of every training view. */
static int edge_maps(ws_respawn *r, ws_view_targets *targets, ws_status *st) {
    const int n = r->train->n;
    const size_t hw = (size_t)r->W * r->H;
    r->edge_distance = ws_malloc((size_t)n * hw * sizeof(float), "edge distance maps", st);
    r->edge_start = r->edge_distance ? ws_calloc((size_t)n + 1, sizeof(int), "edge pixels", st) : NULL;
    int rc = r->edge_start ? WS_OK : st->code;
    size_t cap = 0, count = 0;
    for (int k = 0; k < n && !rc; k++) {
        const float *target;
        rc = ws_view_targets_line(targets, WS_TRAIN, k, &target, st);
        for (size_t p = 0; p < hw && !rc; p++) {
            r->mark[p] = target[p] >= 0.5f;
            if (!r->mark[p]) continue;
            if (count == cap) {
                cap = cap ? 2 * cap : hw;
                int *grown = realloc(r->edge_pixel, cap * sizeof(int));
                if (!grown) {
                    rc = ws_fail(st, WS_ENOMEM, "out of memory allocating %zu bytes for edge pixels", cap * sizeof(int));
                    break;
                }
                r->edge_pixel = grown;
            }
            r->edge_pixel[count++] = (int)p;
        }
        if (!rc) rc = ws_distance_map(r->mark, r->W, r->H, r->edge_distance + k * hw, st);
        r->edge_start[k + 1] = (int)count;
    }
    if (!rc && !(r->uncovered = ws_malloc((count ? count : 1) * sizeof(float), "edge coverage", st)))
        rc = st->code;
    return rc;
}

int ws_respawn_create(ws_respawn **out, const ws_scene *scene, ws_view_targets *targets,
                      const ws_scene_hull *hull, int n_curves,
                      double length, ws_status *st) {
    *out = NULL;
    ws_respawn *r = ws_calloc(1, sizeof *r, "respawn", st);
    if (!r) return st->code;
    r->train = &scene->split[WS_TRAIN];
    r->hull = hull;
    r->W = scene->width;
    r->H = scene->height;
    size_t hw = (size_t)r->W * r->H;
    int rc = ws_view_targets_silhouettes(targets, WS_TRAIN, &r->sil, st);
    if (!rc && (!(r->mark = ws_malloc(hw, "sketch marks", st)) ||
                !(r->sketch_distance = ws_malloc(hw * sizeof(float), "sketch distances", st))))
        rc = st->code;
    if (!rc) rc = edge_maps(r, targets, st);
    /* The stroke length of the initial spread (surface.h), without its rng. */
    const int candidates = ws_hull_surface_candidates(&r->hull->surface);
    int k = n_curves < candidates ? n_curves : candidates, *picked = NULL;
    double spacing = 0;
    ws_rng none;
    ws_rng_seed(&none, 0);
    if (!rc && !(picked = ws_malloc(sizeof(int) * (k ? k : 1), "spread", st))) rc = st->code;
    if (!rc && k > 0) rc = ws_hull_surface_spread(&r->hull->surface, NULL, 0, k, &none, picked, &spacing, st);
    free(picked);
    r->length = fmax(length, 0.5 * spacing);
    if (rc) {
        ws_respawn_free(r);
        return rc;
    }
    *out = r;
    return WS_OK;
}

void ws_respawn_free(ws_respawn *r) {
    if (!r) return;
    free(r->edge_distance);
    free(r->edge_start);
    free(r->edge_pixel);
    free(r->uncovered);
    free(r->mark);
    free(r->sketch_distance);
    free(r);
}

/* Whether the Gaussian (mu, radius) is outside the silhouettes of most of
 * the training views that see it. */
static int gaussian_outside(const ws_respawn *r, const double mu[3], double radius) {
    int seen = 0, outside = 0;
    for (int k = 0; k < r->train->n; k++) {
        const ws_camera *cam = &r->train->views[k].cam;
        const ws_silhouette *s = &r->sil[k];
        double c[3], u, v;
        ws_camera_to_cam(cam, mu, c);
        double d = ws_camera_project(cam, c, &u, &v);
        if (!(d > radius)) continue;
        double reach = cam->focal * radius / d;
        if (u < 0 || v < 0 || u >= cam->width || v >= cam->height) {
            if (s->touches_border) continue;
            seen++;
            outside++;
            continue;
        }
        seen++;
        outside += s->distance[(size_t)(int)v * cam->width + (int)u] > reach + WS_SILHOUETTE_PIXEL_SLACK;
    }
    return 2 * outside > seen;
}

/* Whether the Gaussians [first, first + count) span less than
 * WS_COLLAPSED_EXTENT thicknesses. */
static int collapsed(const ws_gaussians *g, int first, int count, double thickness) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, ext = 0;
    for (int k = first; k < first + count; k++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], g->mu[3 * k + a]);
            hi[a] = fmax(hi[a], g->mu[3 * k + a]);
        }
    for (int a = 0; a < 3 && count > 0; a++) ext += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    return sqrt(ext) < WS_COLLAPSED_EXTENT * thickness;
}

/* first (c->n + 1): curve ci's Gaussians are [first[ci], first[ci + 1]). */
static void curve_offsets(const ws_curves *c, const ws_gaussians *g, int *first) {
    memset(first, 0, sizeof(int) * ((size_t)c->n + 1));
    for (int k = 0; k < g->n; k++) first[g->curve[k] + 1]++;
    for (int ci = 0; ci < c->n; ci++) first[ci + 1] += first[ci];
}

/* The pixel (row i, column j) under world point p in view k; 0 when it
 * is behind the camera or out of the frame. */
static int pixel_of(const ws_respawn *r, int k, const double p[3], int *i, int *j) {
    const ws_camera *cam = &r->train->views[k].cam;
    double c[3], u, v;
    ws_camera_to_cam(cam, p, c);
    double d = ws_camera_project(cam, c, &u, &v);
    if (!(d > 0) || !(u >= 0 && v >= 0 && u < r->W && v < r->H)) return 0;
    *i = (int)v;
    *j = (int)u;
    return 1;
}

/* The share of the projections of the Gaussians [first, first + count)
 * into the training views (those that fall in the frame) that lie within
 * WS_DRAWS_EDGE_PX of an edge pixel (0 when none falls in a frame). */
static double edge_share(const ws_respawn *r, const ws_gaussians *g, int first, int count) {
    const size_t hw = (size_t)r->W * r->H;
    long seen = 0, on = 0;
    for (int q = first; q < first + count; q++)
        for (int k = 0; k < r->train->n; k++) {
            int i, j;
            if (!pixel_of(r, k, g->mu + 3 * q, &i, &j)) continue;
            seen++;
            on += r->edge_distance[k * hw + (size_t)i * r->W + j] <= WS_DRAWS_EDGE_PX;
        }
    return seen ? (double)on / seen : 0;
}

static int curve_idle(const ws_respawn *r, const ws_curves *c, const ws_gaussians *g, int first,
                      int count, const ws_adam *adam, int ci) {
    int moved_ever = 0;
    for (int x = 0; x < WS_CURVE_FLOATS; x++) moved_ever |= adam->v[ci * WS_CURVE_FLOATS + x] > 0;
    if (!moved_ever || collapsed(g, first, count, c->thickness) || edge_share(r, g, first, count) < WS_EDGE_SHARE)
        return 1;
    int outside = 0;
    for (int k = first; k < first + count; k++) outside += gaussian_outside(r, g->mu + 3 * k, c->thickness);
    return 2 * outside > count;
}

/* Every edge pixel's distance to the n points (world, n x 3). */
static int measure_coverage(ws_respawn *r, const double *points, int n, ws_status *st) {
    const size_t hw = (size_t)r->W * r->H;
    for (int k = 0; k < r->train->n; k++) {
        memset(r->mark, 0, hw);
        for (int q = 0; q < n; q++) {
            int i, j;
            if (pixel_of(r, k, points + 3 * q, &i, &j)) r->mark[(size_t)i * r->W + j] = 1;
        }
        if (ws_distance_map(r->mark, r->W, r->H, r->sketch_distance, st)) return st->code;
        for (int e = r->edge_start[k]; e < r->edge_start[k + 1]; e++)
            r->uncovered[e] = r->sketch_distance[r->edge_pixel[e]];
    }
    return WS_OK;
}

/* Lowers every edge pixel's distance to the sketch for the n new points. */
static void add_coverage(ws_respawn *r, const double *points, int n) {
    for (int k = 0; k < r->train->n; k++)
        for (int q = 0; q < n; q++) {
            int i, j;
            if (!pixel_of(r, k, points + 3 * q, &i, &j)) continue;
            for (int e = r->edge_start[k]; e < r->edge_start[k + 1]; e++) {
                int di = r->edge_pixel[e] / r->W - i, dj = r->edge_pixel[e] % r->W - j;
                r->uncovered[e] = fminf(r->uncovered[e], sqrtf((float)(di * di + dj * dj)));
            }
        }
}

/* World point at camera depth t on the ray through image point (u, v) of
 * camera cam. */
static void ray_point(const ws_camera *cam, double u, double v, double t, double p[3]) {
    double dir[3];
    ws_camera_ray(cam, u, v, dir);
    for (int a = 0; a < 3; a++)
        p[a] = cam->c2w[a][0] * t * dir[0] + cam->c2w[a][1] * t * dir[1] + cam->c2w[a][2] * t * dir[2] +
               cam->c2w[a][3];
}

/* Whether world point p lies in the hull. */
static int in_hull(const ws_hull *h, const double p[3]) {
    int x[3];
    for (int a = 0; a < 3; a++) {
        double f = floor((p[a] - h->origin[a]) / h->voxel);
        if (!(f >= 0 && f < h->n[a])) return 0;
        x[a] = (int)f;
    }
    return ws_hull_in(h, ws_hull_index(h, x[0], x[1], x[2]));
}

/* The depth of the edge under (u, v) of view k (see respawn.h), searched
 * in [lo, hi]; 0 when the ray meets no hull voxel there. */
static double edge_depth(const ws_respawn *r, int k, double u, double v, double lo_depth, double hi_depth) {
    const ws_camera *cam = &r->train->views[k].cam;
    const ws_hull *h = &r->hull->hull;
    const size_t hw = (size_t)r->W * r->H;
    /* the depths where the ray is inside the grid's box (slabs) */
    double o[3], far_point[3], t0 = lo_depth, t1 = hi_depth;
    ray_point(cam, u, v, 0, o);
    ray_point(cam, u, v, 1, far_point);
    for (int a = 0; a < 3; a++) {
        double step = far_point[a] - o[a], lo = h->origin[a], hi = lo + h->n[a] * h->voxel;
        if (fabs(step) < 1e-12) {
            if (o[a] < lo || o[a] > hi) return 0;
            continue;
        }
        double ta = (lo - o[a]) / step, tb = (hi - o[a]) / step;
        t0 = fmax(t0, fmin(ta, tb));
        t1 = fmin(t1, fmax(ta, tb));
    }
    double per_depth = sqrt((far_point[0] - o[0]) * (far_point[0] - o[0]) + (far_point[1] - o[1]) * (far_point[1] - o[1]) +
                            (far_point[2] - o[2]) * (far_point[2] - o[2]));
    double dt = 0.5 * h->voxel / per_depth; /* half a voxel along the ray */
    double best_t = 0, run_end = 0;
    int best = -1, in_run = 0;
    for (double t = t0 + 0.5 * dt; t < t1; t += dt) {
        double p[3];
        ray_point(cam, u, v, t, p);
        int votes = -1; /* outside the hull */
        if (in_hull(h, p)) {
            votes = 0;
            for (int m = 0; m < r->train->n; m++) {
                int i, j;
                if (m != k && pixel_of(r, m, p, &i, &j))
                    votes += r->edge_distance[m * hw + (size_t)i * r->W + j] <= WS_ON_EDGE_PX;
            }
        }
        if (votes > best) {
            best = votes;
            best_t = run_end = t;
            in_run = 1;
        } else if (in_run && votes == best) {
            run_end = t;
        } else {
            in_run = 0;
        }
    }
    return best >= 0 ? 0.5 * (best_t + run_end) : 0;
}

/* The unit image direction (du, dv) of the edge at pixel (i, j) of view k:
 * the principal axis of the edge pixels within DIRECTION_RADIUS. */
static void edge_direction(const ws_respawn *r, int k, int i, int j, double *du, double *dv) {
    const float *ed = r->edge_distance + (size_t)k * r->W * r->H;
    double sxx = 0, sxy = 0, syy = 0;
    for (int y = i - DIRECTION_RADIUS; y <= i + DIRECTION_RADIUS; y++)
        for (int x = j - DIRECTION_RADIUS; x <= j + DIRECTION_RADIUS; x++) {
            if (y < 0 || x < 0 || y >= r->H || x >= r->W || ed[(size_t)y * r->W + x] != 0) continue;
            sxx += (double)(x - j) * (x - j);
            sxy += (double)(x - j) * (y - i);
            syy += (double)(y - i) * (y - i);
        }
    double angle = 0.5 * atan2(2 * sxy, sxx - syy);
    *du = cos(angle);
    *dv = sin(angle);
}

/* How far (px, up to `most`) the edge goes on from (u, v) along (du, dv). */
static double edge_run(const ws_respawn *r, int k, double u, double v, double du, double dv, double most) {
    const float *ed = r->edge_distance + (size_t)k * r->W * r->H;
    double s = 0;
    while (s + 1 <= most) {
        double x = u + (s + 1) * du, y = v + (s + 1) * dv;
        if (!(x >= 0 && y >= 0 && x < r->W && y < r->H) || ed[(size_t)(int)y * r->W + (int)x] > WS_ON_EDGE_PX)
            break;
        s += 1;
    }
    return s;
}

/* Places curve ci on the farthest uncovered edge pixel (see respawn.h);
 * *placed = 0 when no edge pixel is uncovered. points: room for the
 * stroke's sample points (WS_MAX_GAUSSIANS_PER_CURVE x 3). */
static void place_on_edge(ws_respawn *r, ws_curves *c, int ci, double *points, int *placed) {
    *placed = 0;
    const int views = r->train->n;
    for (;;) {
        int e = -1;
        for (int x = 0; x < r->edge_start[views]; x++)
            if (r->uncovered[x] >= WS_UNCOVERED_PX && (e < 0 || r->uncovered[x] > r->uncovered[e])) e = x;
        if (e < 0) return;
        int k = 0;
        while (r->edge_start[k + 1] <= e) k++;
        const ws_camera *cam = &r->train->views[k].cam;
        int i = r->edge_pixel[e] / r->W, j = r->edge_pixel[e] % r->W;
        double u = j + WS_PIXEL_CENTER, v = i + WS_PIXEL_CENTER;
        double t = edge_depth(r, k, u, v, 0, INFINITY);
        if (!(t > 0)) {
            r->uncovered[e] = 0; /* no hull behind it: not an edge of the object */
            continue;
        }
        double du, dv;
        edge_direction(r, k, i, j, &du, &dv);
        double most = fmin(r->uncovered[e], 0.5 * r->length * cam->focal / t);
        double reach[2] = {-edge_run(r, k, u, v, -du, -dv, most), edge_run(r, k, u, v, du, dv, most)};
        double end[2][3], mid[3], dir[3], len = 0;
        for (int side = 0; side < 2; side++) {
            /* each end triangulated on its own ray, near the middle's depth */
            double ue = u + reach[side] * du, ve = v + reach[side] * dv;
            double window = END_SLOPE * fabs(reach[side]) * t / cam->focal;
            double te = reach[side] != 0 ? edge_depth(r, k, ue, ve, fmax(0, t - window), t + window) : t;
            ray_point(cam, ue, ve, te > 0 ? te : t, end[side]);
        }
        for (int x = 0; x < 3; x++) {
            mid[x] = 0.5 * (end[0][x] + end[1][x]);
            dir[x] = end[1][x] - end[0][x];
            len += dir[x] * dir[x];
        }
        len = sqrt(len);
        if (len > 0) {
            for (int x = 0; x < 3; x++) dir[x] /= len;
        } else { /* a single pixel: along the image's direction at that depth */
            double b[3], norm = 0;
            ray_point(cam, u + du, v + dv, t, b);
            for (int x = 0; x < 3; x++) {
                dir[x] = b[x] - mid[x];
                norm += dir[x] * dir[x];
            }
            for (int x = 0; x < 3; x++) dir[x] /= sqrt(norm);
        }
        len = fmax(len, 2 * WS_COLLAPSED_EXTENT * c->thickness);
        ws_curve_set_segment(c, ci, mid, dir, len);
        double spacing = 2 * c->thickness * (1 - c->overlap);
        int n = (int)fmin(len / spacing, WS_MAX_GAUSSIANS_PER_CURVE - 1) + 1;
        for (int q = 0; q < n; q++)
            ws_curve_point(c, ci, n > 1 ? (double)q / (n - 1) : 0.5, points + 3 * q);
        add_coverage(r, points, n);
        *placed = 1;
        return;
    }
}

/* A unit tangent at a surface point: the axis least aligned with the
 * normal, made orthogonal to it (any axis for a zero normal). */
static void tangent(const double n[3], double t[3]) {
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (fabs(n[a]) < fabs(n[axis])) axis = a;
    double e[3] = {0, 0, 0};
    e[axis] = 1;
    double along = e[0] * n[0] + e[1] * n[1] + e[2] * n[2], len = 0;
    for (int a = 0; a < 3; a++) {
        t[a] = e[a] - along * n[a];
        len += t[a] * t[a];
    }
    len = sqrt(len);
    for (int a = 0; a < 3; a++) t[a] /= len;
}

/* Places curve ci on the hull's surface point farthest from the kept
 * centres (keep, nkeep of them; the stroke's middle is appended). */
/* The surface points' squared distances to keep[0..upto) (hull_nearest),
 * caught up with the points kept since, so that each curve placed on the
 * hull costs one pass over the surface, not one per kept Gaussian (25,000
 * curves took a respawn past 16 minutes). */
typedef struct {
    double *nearest; /* surface.n, NULL until the first placement on the hull */
    int upto;
} hull_nearest;

static int place_on_hull(ws_respawn *r, ws_curves *c, int ci, double *keep, int *nkeep, hull_nearest *h,
                         ws_status *st) {
    const ws_hull_surface *surface = &r->hull->surface;
    int at;
    double dir[3];
    if (*nkeep == 0) { /* nothing to keep away from: the spread draws one */
        double spacing;
        ws_rng unused;
        ws_rng_seed(&unused, (uint64_t)ci);
        if (ws_hull_surface_spread(surface, keep, *nkeep, 1, &unused, &at, &spacing, st)) return st->code;
    } else {
        if (!h->nearest) {
            if (!(h->nearest = ws_malloc(sizeof(double) * (surface->n ? surface->n : 1), "surface distances", st)))
                return st->code;
            for (int i = 0; i < surface->n; i++) h->nearest[i] = INFINITY;
        }
        ws_hull_surface_nearer(surface, keep + 3 * h->upto, *nkeep - h->upto, h->nearest);
        h->upto = *nkeep;
        if ((at = ws_hull_surface_farthest(surface, h->nearest)) < 0)
            return ws_fail(st, WS_EINTERNAL, "respawn: no surface point to place a curve on");
    }
    tangent(surface->normal + 3 * at, dir);
    ws_curve_set_segment(c, ci, r->hull->surface.p + 3 * at, dir, r->length);
    memcpy(keep + 3 * (*nkeep)++, r->hull->surface.p + 3 * at, sizeof(double) * 3);
    return WS_OK;
}

int ws_respawn_step(ws_respawn *r, ws_curves *c, ws_adam *adam, int *moved, ws_status *st) {
    *moved = 0;
    ws_gaussians g = {0};
    if (ws_curves_sample(c, &g, st)) return st->code;
    int *idle = ws_calloc(c->n, sizeof *idle, "idle curves", st);
    int *first = idle ? ws_malloc(sizeof(int) * ((size_t)c->n + 1), "curve offsets", st) : NULL;
    double *keep = first ? ws_malloc(sizeof(double) * 3 * ((size_t)g.n + c->n), "kept centres", st) : NULL;
    double *points = keep ? ws_malloc(sizeof(double) * 3 * WS_MAX_GAUSSIANS_PER_CURVE, "stroke points", st) : NULL;
    if (!points) {
        free(idle);
        free(first);
        free(keep);
        ws_gaussians_free(&g);
        return st->code;
    }
    curve_offsets(c, &g, first);
    int any = 0;
    #pragma omp parallel for schedule(dynamic, 1) reduction(| : any)
    for (int ci = 0; ci < c->n; ci++) {
        idle[ci] = curve_idle(r, c, &g, first[ci], first[ci + 1] - first[ci], adam, ci);
        any |= idle[ci];
    }
    int nkeep = 0;
    for (int k = 0; k < g.n; k++)
        if (!idle[g.curve[k]]) memcpy(keep + 3 * nkeep++, g.mu + 3 * k, sizeof(double) * 3);
    int rc = any ? measure_coverage(r, keep, nkeep, st) : WS_OK;
    hull_nearest near = {NULL, 0};
    for (int ci = 0; ci < c->n && !rc && any; ci++) {
        if (!idle[ci]) continue;
        int placed;
        place_on_edge(r, c, ci, points, &placed);
        if (placed) {
            double mid[3];
            ws_curve_point(c, ci, 0.5, mid);
            memcpy(keep + 3 * nkeep++, mid, sizeof(double) * 3);
        } else if ((rc = place_on_hull(r, c, ci, keep, &nkeep, &near, st))) {
            break;
        }
        memset(adam->m + (size_t)ci * WS_CURVE_FLOATS, 0, sizeof(double) * WS_CURVE_FLOATS);
        memset(adam->v + (size_t)ci * WS_CURVE_FLOATS, 0, sizeof(double) * WS_CURVE_FLOATS);
        ++*moved;
    }
    free(near.nearest);
    free(idle);
    free(first);
    free(keep);
    free(points);
    ws_gaussians_free(&g);
    return rc;
}

int ws_respawn_retire(const ws_respawn *r, const ws_curves *c, int *retire, ws_status *st) {
    ws_gaussians g = {0};
    int *first = ws_malloc(sizeof(int) * ((size_t)c->n + 1), "curve offsets", st);
    if (!first || ws_curves_sample(c, &g, st)) {
        free(first);
        return st->code;
    }
    curve_offsets(c, &g, first);
    for (int ci = 0; ci < c->n; ci++) {
        int n = first[ci + 1] - first[ci];
        retire[ci] = collapsed(&g, first[ci], n, c->thickness) || edge_share(r, &g, first[ci], n) < WS_EDGE_SHARE;
    }
    free(first);
    ws_gaussians_free(&g);
    return WS_OK;
}
