/* edge_consensus.c: the edges the views agree on inside the region of
 * interest (see edge_consensus.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "base/progress.h"
#include "base/sym3.h"
#include "geometry/view_spread.h"
#include "objective/edge_consensus.h"
#include "objective/line_target.h"
#include "render/convex_fill.h"
#include "render/distance.h"
#include "render/thin_edges.h"

/* The direction in [0, pi) of the photo's (3 x H x W) luminance gradient
 * at pixel (i, j): 3 x 3 Sobel, borders repeated. */
static float gradient_angle(const float *photo, int W, int H, int i, int j) {
    const size_t hw = (size_t)W * H;
    double y[3][3];
    for (int a = -1; a <= 1; a++)
        for (int b = -1; b <= 1; b++) {
            int ii = i + a < 0 ? 0 : i + a >= H ? H - 1 : i + a, jj = j + b < 0 ? 0 : j + b >= W ? W - 1 : j + b;
            size_t q = (size_t)ii * W + jj;
            y[a + 1][b + 1] = 0.299 * photo[q] + 0.587 * photo[hw + q] + 0.114 * photo[2 * hw + q];
        }
    double gx = y[0][2] + 2 * y[1][2] + y[2][2] - y[0][0] - 2 * y[1][0] - y[2][0];
    double gy = y[2][0] + 2 * y[2][1] + y[2][2] - y[0][0] - 2 * y[0][1] - y[0][2];
    double t = atan2(gy, gx);
    return (float)(t < 0 ? t + M_PI : t >= M_PI ? t - M_PI : t);
}

/* angle (H x W): at each pixel, the direction in [0, pi) of the photo's
 * luminance gradient (gradient_angle) at the nearest pixel of edge within
 * WS_CONSENSUS_ORIENT_REACH pixels (first in row order among equals); NAN
 * where there is none. */
static void edge_angles(const float *photo, const float *edge, int W, int H, float *grad, float *angle) {
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++)
            if (edge[(size_t)i * W + j] >= 0.5f) grad[(size_t)i * W + j] = gradient_angle(photo, W, H, i, j);
    const int R = WS_CONSENSUS_ORIENT_REACH;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            int best = R * R + 1;
            float at = NAN;
            for (int a = -R; a <= R; a++)
                for (int b = -R; b <= R; b++) {
                    int ii = i + a, jj = j + b;
                    if (ii < 0 || ii >= H || jj < 0 || jj >= W || a * a + b * b >= best ||
                        !(edge[(size_t)ii * W + jj] >= 0.5f))
                        continue;
                    best = a * a + b * b;
                    at = grad[(size_t)ii * W + jj];
                }
            angle[(size_t)i * W + j] = at;
        }
}

/* dist, angle (n x H x W): D_v of each of the n views, and its
 * edge_angles. */
static int edge_maps(const ws_view *const *views, int n, float *dist, float *angle, ws_status *st) {
    const int W = views[0]->photo.width, H = views[0]->photo.height;
    const size_t hw = (size_t)W * H;
    float *edge = ws_malloc(hw * sizeof *edge, "edge consensus", st);
    float *grad = edge ? ws_malloc(hw * sizeof *grad, "edge consensus", st) : NULL;
    uint8_t *set = grad ? ws_malloc(hw, "edge consensus", st) : NULL;
    int rc = set ? WS_OK : st->code;
    for (int v = 0; v < n && !rc; v++) {
        const ws_image *photo = &views[v]->photo;
        if (photo->width != W || photo->height != H) {
            rc = ws_fail(st, WS_EINTERNAL, "edge consensus: view %d is %d x %d, view 0 %d x %d", v, photo->width,
                         photo->height, W, H);
            break;
        }
        if (!(rc = ws_thin_edges(photo->data, W, H, edge, st))) {
            for (size_t p = 0; p < hw; p++) set[p] = edge[p] >= 0.5f;
            rc = ws_distance_map(set, W, H, dist + v * hw, st);
            edge_angles(photo->data, edge, W, H, grad, angle + v * hw);
        }
    }
    free(edge);
    free(grad);
    free(set);
    return rc;
}


#define WORDS ((WS_CONSENSUS_MAX_VIEWS + 63) / 64)
#define CAPS 26

/* What the votes read (edge_consensus.h). */
typedef struct {
    const ws_view **views;    /* the train views that vote: WS_CONSENSUS_MAX_VIEWS at most, spread */
    int nviews;
    const float *dist, *angle;
    double rho;               /* a grid cube's circumscribed radius */
    const float *depth;       /* NULL, or nviews x H x W: the photo hull's nearest surface (photo_hull.h) */
    double behind;            /* how far behind it a point still counts as seen */
    uint64_t cap[CAPS][WORDS]; /* the views of each cap, one bit each */
} votes;

/* x->cap: the views whose direction from centre lies within
 * WS_CONSENSUS_CAP_ANGLE of each of the 26 directions from a cube's centre
 * to its neighbours'. */
static void view_caps(votes *x, const double centre[3]) {
    memset(x->cap, 0, sizeof x->cap);
    const double cosine = cos(WS_CONSENSUS_CAP_ANGLE * M_PI / 180);
    double dir[WS_CONSENSUS_MAX_VIEWS][3];
    for (int v = 0; v < x->nviews; v++) ws_view_direction(&x->views[v]->cam, centre, dir[v]);
    int k = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                if (!dx && !dy && !dz) continue;
                const double len = sqrt(dx * dx + dy * dy + dz * dz);
                for (int v = 0; v < x->nviews; v++)
                    if (dx * dir[v][0] + dy * dir[v][1] + dz * dir[v][2] > cosine * len)
                        x->cap[k][v / 64] |= 1ull << (v % 64);
                k++;
            }
}

/* 2 where grid point p is strong, 1 where it is weak, else 0
 * (edge_consensus.h). */
static uint8_t vote(const votes *x, const double p[3], int8_t dir[3]) {
    uint64_t seen[WORDS] = {0}, hit[WORDS] = {0};
    double normal[WS_CONSENSUS_MAX_VIEWS][3];
    int view[WS_CONSENSUS_MAX_VIEWS], nhit = 0;
    for (int v = 0; v < x->nviews; v++) {
        const ws_camera *cam = &x->views[v]->cam;
        double c[3], u, w;
        ws_camera_to_cam(cam, p, c);
        double d = ws_camera_project(cam, c, &u, &w);
        if (!(d > x->rho) || !(u >= 0 && u < cam->width && w >= 0 && w < cam->height)) continue;
        size_t at = ((size_t)v * cam->height + (size_t)w) * cam->width + (size_t)u;
        if (x->depth && !(d <= x->depth[at] + x->behind)) continue; /* hidden by the object */
        seen[v / 64] |= 1ull << (v % 64);
        float angle = x->angle[at];
        if (!(x->dist[at] <= WS_CONSENSUS_VOTE_PX + cam->focal * x->rho / (2 * d)) || isnan(angle)) continue;
        /* the plane through the camera and the image's edge line there:
         * the ray to (u, w) crossed with the line's direction (-gy, gx) */
        double ray[3], e[3] = {-sin(angle) / cam->focal, -cos(angle) / cam->focal, 0}, n[3];
        ws_camera_ray(cam, u, w, ray);
        n[0] = ray[1] * e[2] - ray[2] * e[1];
        n[1] = ray[2] * e[0] - ray[0] * e[2];
        n[2] = ray[0] * e[1] - ray[1] * e[0];
        double len = 0;
        for (int k = 0; k < 3; k++) {
            normal[nhit][k] = cam->R[0][k] * n[0] + cam->R[1][k] * n[1] + cam->R[2][k] * n[2];
            len += normal[nhit][k] * normal[nhit][k];
        }
        if (!(len > 0)) continue;
        for (int k = 0; k < 3; k++) normal[nhit][k] /= sqrt(len);
        view[nhit++] = v;
    }
    /* the direction the hit views' edges agree on, found twice: from all
     * of them, then from those that agree with the first answer */
    const double tolerance = sin(WS_CONSENSUS_ORIENT_DEG * M_PI / 180);
    double t[3] = {0, 0, 0};
    for (int pass = 0; pass < 2; pass++) {
        double m[6] = {0, 0, 0, 0, 0, 0};
        for (int h = 0; h < nhit; h++) {
            const double *n = normal[h];
            if (pass && fabs(n[0] * t[0] + n[1] * t[1] + n[2] * t[2]) > tolerance) continue;
            m[0] += n[0] * n[0], m[1] += n[1] * n[1], m[2] += n[2] * n[2];
            m[3] += n[0] * n[1], m[4] += n[0] * n[2], m[5] += n[1] * n[2];
        }
        ws_sym3_least_eigenvector(m, t);
    }
    for (int k = 0; k < 3; k++) dir[k] = (int8_t)lrint(127 * t[k]);
    for (int h = 0; h < nhit; h++) {
        const double *n = normal[h];
        if (fabs(n[0] * t[0] + n[1] * t[1] + n[2] * t[2]) <= tolerance) hit[view[h] / 64] |= 1ull << (view[h] % 64);
    }
    int all = 0, all_hit = 0;
    for (int w = 0; w < WORDS; w++) all += __builtin_popcountll(seen[w]), all_hit += __builtin_popcountll(hit[w]);
    if (all >= WS_CONSENSUS_MIN_VIEWS && all_hit >= WS_CONSENSUS_STRONG * all) return 2;
    const int need = x->nviews / 4 > WS_CONSENSUS_MIN_VIEWS ? x->nviews / 4 : WS_CONSENSUS_MIN_VIEWS;
    for (int k = 0; k < CAPS; k++) {
        int s = 0, h = 0;
        for (int w = 0; w < WORDS; w++)
            s += __builtin_popcountll(seen[w] & x->cap[k][w]), h += __builtin_popcountll(hit[w] & x->cap[k][w]);
        if (s >= need && h >= WS_CONSENSUS_WEAK * s) return 1;
    }
    return 0;
}

/* Keeps the parts of keep (n[0] x n[1] x n[2]; 0 = out, 1 = weak, 2 =
 * strong) that hold at least min_part strong points, as 1; the rest 0. A
 * part grows from a strong point to its 26 neighbours, from a weak point
 * only to the points up to WS_CONSENSUS_WEAK_REACH cubes away along its
 * edge's direction (dir: 127 t, t the direction its hits agree on; offsets
 * within acos(WS_CONSENSUS_ALONG) of it), across a missing point:
 * an edge of the object is a line of grid points, while the points that
 * agree by chance with a busy background's parallel lines fill sheets and
 * blobs. stack: as many longs as keep has points; a part's points are kept
 * at its far end while its flood fill uses the near end (|= 4: reached). */
static void keep_parts(uint8_t *keep, const int8_t *dir, const int n[3], long min_part, long *stack) {
    const long total = (long)n[0] * n[1] * n[2];
    for (long start = 0; start < total; start++) {
        if (keep[start] != 1 && keep[start] != 2) continue;
        long top = 0, count = 0, strong = 0;
        stack[top++] = start;
        keep[start] |= 4;
        while (top > 0) {
            long k = stack[--top];
            stack[total - 1 - count++] = k;
            strong += (keep[k] & 3) == 2;
            const int8_t *t = dir + 3 * k;
            const double tt = sqrt((double)t[0] * t[0] + (double)t[1] * t[1] + (double)t[2] * t[2]);
            int x = (int)(k % n[0]), y = (int)(k / n[0] % n[1]), z = (int)(k / ((long)n[0] * n[1]));
            const int r = (keep[k] & 3) == 1 ? WS_CONSENSUS_WEAK_REACH : 1;
            for (int dz = -r; dz <= r; dz++)
                for (int dy = -r; dy <= r; dy++)
                    for (int dx = -r; dx <= r; dx++) {
                        int xx = x + dx, yy = y + dy, zz = z + dz;
                        if (xx < 0 || xx >= n[0] || yy < 0 || yy >= n[1] || zz < 0 || zz >= n[2]) continue;
                        long q = ((long)zz * n[1] + yy) * n[0] + xx;
                        if (keep[q] != 1 && keep[q] != 2) continue;
                        double along = fabs((double)(dx * t[0] + dy * t[1] + dz * t[2]));
                        if ((keep[k] & 3) == 1 && !(along >= WS_CONSENSUS_ALONG * tt * sqrt(dx * dx + dy * dy + dz * dz)))
                            continue;
                        keep[q] |= 4;
                        stack[top++] = q;
                    }
        }
        uint8_t mark = strong >= min_part ? 8 : 0;
        for (long c = 0; c < count; c++) keep[stack[total - 1 - c]] = mark;
    }
    for (long k = 0; k < total; k++) keep[k] = keep[k] == 8;
}

/* p: the centre of grid point k (x fastest) of the grid of spacing voxel
 * (n cubes along each axis) from roi->lo. */
static void grid_point(const ws_roi *roi, double voxel, const int n[3], long k, double p[3]) {
    const long x = k % n[0], y = k / n[0] % n[1], z = k / ((long)n[0] * n[1]);
    p[0] = roi->lo[0] + (x + 0.5) * voxel;
    p[1] = roi->lo[1] + (y + 0.5) * voxel;
    p[2] = roi->lo[2] + (z + 0.5) * voxel;
}

/* keep, dir (grid n, x fastest): each grid point's vote, then the kept
 * parts (keep_parts) less the points on a support's own lines
 * (support_plane.h). */
static void vote_grid(const votes *x, const ws_roi *roi, double voxel, const int n[3], const ws_support_plane *support,
                      uint8_t *keep, int8_t *dir, long *stack, ws_progress *progress) {
    ws_progress_begin(progress, "the views' vote on the region's edges", "slices of its grid", n[2]);
#pragma omp parallel for schedule(dynamic)
    for (int z = 0; z < n[2]; z++) {
        for (int y = 0; y < n[1]; y++)
            for (int i = 0; i < n[0]; i++) {
                const long k = ((long)z * n[1] + y) * n[0] + i;
                double p[3];
                grid_point(roi, voxel, n, k, p);
                keep[k] = vote(x, p, dir + 3 * k);
            }
        ws_progress_advance(progress, 1);
    }
    ws_progress_end(progress);
    const long total = (long)n[0] * n[1] * n[2];
    keep_parts(keep, dir, n, WS_CONSENSUS_MIN_PART, stack);
    for (long k = 0; support->found && k < total; k++) {
        double p[3];
        grid_point(roi, voxel, n, k, p);
        if (keep[k] && ws_support_plane_holds(support, p)) keep[k] = 0;
    }
}

int ws_edge_consensus_make(const ws_scene *scene, const ws_roi *roi, int resolution, ws_edge_consensus *c,
                           ws_status *st) {
    memset(c, 0, sizeof *c);
    const ws_split *train = &scene->split[WS_TRAIN];
    if (ws_photo_hull_make(scene, roi, resolution, &c->hull, st) ||
        ws_support_plane_find(&c->hull, train, &c->support, st) || ws_support_plane_carve(&c->support, &c->hull, st)) {
        ws_edge_consensus_free(c);
        return st->code;
    }
    c->roi = *roi;
    c->voxel = c->hull.voxel; /* the points vote on the hull's grid */
    const int n[3] = {c->hull.n[0], c->hull.n[1], c->hull.n[2]};
    c->tested = (long)n[0] * n[1] * n[2];
    const size_t hw = (size_t)scene->width * scene->height;
    double centre[3];
    ws_roi_centre(roi, centre);
    int nviews = 0;
    const ws_view **views = ws_malloc(sizeof *views * WS_CONSENSUS_MAX_VIEWS, "edge consensus", st);
    int rc = views ? ws_view_spread(train, centre, WS_CONSENSUS_MAX_VIEWS, views, &nviews, st) : st->code;
    const size_t maps = hw * (size_t)(nviews ? nviews : 1);
    float *dist = rc ? NULL : ws_malloc(maps * sizeof *dist, "edge consensus", st);
    float *angle = dist ? ws_malloc(maps * sizeof *angle, "edge consensus", st) : NULL;
    uint8_t *keep = angle ? ws_calloc((size_t)c->tested, 1, "edge consensus", st) : NULL;
    int8_t *dir = keep ? ws_malloc((size_t)c->tested * 3, "edge consensus", st) : NULL;
    if (!rc && !dir) rc = st->code;
    if (!rc && nviews) rc = edge_maps(views, nviews, dist, angle, st);
    votes *x = rc ? NULL : ws_malloc(sizeof *x, "edge consensus", st);
    long *stack = x ? ws_malloc(sizeof *stack * (size_t)c->tested, "edge consensus", st) : NULL;
    if (!rc && !stack) rc = st->code;
    float *depth = rc ? NULL : ws_malloc(maps * sizeof *depth, "edge consensus", st);
    if (!rc && !depth) rc = st->code;
    for (int v = 0; !rc && v < nviews; v++) ws_photo_hull_project(&c->hull, &views[v]->cam, depth + v * hw, NULL);
    if (!rc) {
        *x = (votes){views, nviews, dist, angle, c->voxel * sqrt(3.0) / 2, depth,
                     WS_PHOTO_HULL_DEPTH_TOL * c->hull.voxel, {{0}}};
        view_caps(x, centre);
        vote_grid(x, roi, c->voxel, n, &c->support, keep, dir, stack, scene->progress);
        for (long k = 0; k < c->tested; k++) c->n += keep[k];
        if (c->n == 0) { /* the hull hides everything: the photos' colours did not tell the object */
            ws_photo_hull_free(&c->hull);
            x->depth = NULL;
            vote_grid(x, roi, c->voxel, n, &c->support, keep, dir, stack, scene->progress);
            for (long k = 0; k < c->tested; k++) c->n += keep[k];
        }
        c->solid = c->hull.occupied && !c->support.found && c->hull.kept >= WS_CONSENSUS_SOLID * c->n;
    }
    free(x);
    free(stack);
    free(depth);
    if (!rc) {
        c->p = ws_malloc(sizeof *c->p * 3 * (size_t)(c->n ? c->n : 1), "edge consensus", st);
        c->t = c->p ? ws_malloc(sizeof *c->t * 3 * (size_t)(c->n ? c->n : 1), "edge consensus", st) : NULL;
        if (!c->t) rc = st->code;
    }
    if (!rc) {
        int m = 0;
        for (long k = 0; k < c->tested; k++) {
            if (!keep[k]) continue;
            double len = sqrt((double)dir[3 * k] * dir[3 * k] + (double)dir[3 * k + 1] * dir[3 * k + 1] +
                              (double)dir[3 * k + 2] * dir[3 * k + 2]);
            for (int a = 0; a < 3; a++) c->t[3 * m + a] = len > 0 ? dir[3 * k + a] / len : 0;
            grid_point(roi, c->voxel, n, k, c->p + 3 * m++);
        }
    }
    free(views);
    free(dist);
    free(angle);
    free(keep);
    free(dir);
    if (rc) ws_edge_consensus_free(c);
    return rc;
}

void ws_edge_consensus_free(ws_edge_consensus *c) {
    ws_photo_hull_free(&c->hull);
    ws_support_plane_free(&c->support);
    free(c->p);
    free(c->t);
    c->p = c->t = NULL;
    c->n = 0;
}

int ws_edge_consensus_near(const ws_edge_consensus *c, const ws_camera *cam, float *near, ws_status *st) {
    const int W = cam->width, H = cam->height;
    uint8_t *set = ws_calloc((size_t)W * H, 1, "edge consensus", st);
    if (!set) return st->code;
    for (int k = 0; k < c->n; k++) {
        double q[3], u, w;
        ws_camera_to_cam(cam, c->p + 3 * (size_t)k, q);
        if (!(ws_camera_project(cam, q, &u, &w) > 0) || !(u >= 0 && u < W && w >= 0 && w < H)) continue;
        set[(size_t)w * W + (size_t)u] = 1;
    }
    int rc = ws_distance_map(set, W, H, near, st);
    free(set);
    return rc;
}

/* mask (cam->height x cam->width): the photo hull's own mask in cam, a
 * solid's made convex (edge_consensus.h). */
static int hull_mask(const ws_edge_consensus *c, const ws_camera *cam, float *mask, ws_status *st) {
    ws_photo_hull_project(&c->hull, cam, NULL, mask);
    return c->solid ? ws_convex_fill(mask, cam->width, cam->height, st) : WS_OK;
}

/* A wire's hull: neither a solid's nor over a support (edge_consensus.h). */
static int wire_hull(const ws_edge_consensus *c) {
    return c->hull.occupied && !c->solid && !c->support.found;
}

double ws_edge_consensus_band_px(const ws_edge_consensus *c) {
    return c->hull.occupied && !wire_hull(c) ? WS_CONSENSUS_SOLID_BAND_PX : WS_CONSENSUS_SILHOUETTE_PX;
}

int ws_edge_consensus_silhouette(const ws_edge_consensus *c, const ws_view *v, ws_silhouette *s, ws_status *st) {
    const ws_camera *cam = &v->cam;
    const size_t hw = (size_t)cam->width * cam->height;
    ws_image mask = {0};
    float *hull = ws_malloc(hw * sizeof *hull, "edge consensus", st);
    if (!hull || ws_image_alloc(&mask, cam->width, cam->height, 1, st)) {
        free(hull);
        return st->code;
    }
    int rc = ws_edge_consensus_near(c, cam, mask.data, st);
    if (!rc && c->hull.occupied) rc = hull_mask(c, cam, hull, st);
    const double band = ws_edge_consensus_band_px(c);
    if (!rc) {
        for (size_t p = 0; p < hw; p++)
            mask.data[p] = mask.data[p] <= band && (!c->hull.occupied || hull[p] > 0.5f);
        rc = ws_silhouette_make(&v->photo, &mask, s, st);
        /* the kept points are all there is of the object: a view says
         * what lies beyond its frame too (a band cut by the frame's edge
         * would leave the hull unbounded there) */
        if (!rc) s->touches_border = 0;
    }
    ws_image_free(&mask);
    free(hull);
    return rc;
}

/* Sets to 0 each pixel of edge (H x W) whose photo edge runs across every
 * kept point within WS_CONSENSUS_KEEP_PX of it: the line through the pixel
 * (perpendicular to the luminance gradient there) lies more than
 * WS_CONSENSUS_ORIENT_DEG from each such point's t as projected into the
 * view. A point whose t runs along the ray (a cube's step along it projects
 * shorter than WS_CONSENSUS_ALONG_RAY_PX) agrees with any. */
static int orientation_filter(const ws_edge_consensus *c, const ws_view *v, float *edge, ws_status *st) {
    const ws_camera *cam = &v->cam;
    const int W = cam->width, H = cam->height;
    const size_t hw = (size_t)W * H;
    int *head = ws_malloc(hw * sizeof *head, "edge consensus", st);
    int *next = head ? ws_malloc(sizeof *next * (size_t)(c->n ? c->n : 1), "edge consensus", st) : NULL;
    float *along = next ? ws_malloc(sizeof *along * (size_t)(c->n ? c->n : 1), "edge consensus", st) : NULL;
    if (!along) {
        free(head);
        free(next);
        return st->code;
    }
    for (size_t p = 0; p < hw; p++) head[p] = -1;
    for (int k = 0; k < c->n; k++) {
        double q[3], e[3], b[3], u, w, ue, we;
        for (int a = 0; a < 3; a++) e[a] = c->p[3 * k + a] + c->voxel * c->t[3 * k + a];
        ws_camera_to_cam(cam, c->p + 3 * (size_t)k, q);
        ws_camera_to_cam(cam, e, b);
        if (!(ws_camera_project(cam, q, &u, &w) > 0) || !(u >= 0 && u < W && w >= 0 && w < H)) continue;
        along[k] = NAN;
        if (ws_camera_project(cam, b, &ue, &we) > 0 && hypot(ue - u, we - w) >= WS_CONSENSUS_ALONG_RAY_PX) {
            double a = atan2(we - w, ue - u);
            along[k] = (float)(a < 0 ? a + M_PI : a >= M_PI ? a - M_PI : a);
        }
        size_t at = (size_t)w * W + (size_t)u;
        next[k] = head[at];
        head[at] = k;
    }
    const int R = (int)WS_CONSENSUS_KEEP_PX;
    const double tolerance = sin(WS_CONSENSUS_ORIENT_DEG * M_PI / 180);
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            size_t p = (size_t)i * W + j;
            if (!(edge[p] > 0)) continue;
            double line = gradient_angle(v->photo.data, W, H, i, j) + M_PI / 2;
            int agree = 0;
            for (int a = -R; a <= R && !agree; a++)
                for (int b = -R; b <= R && !agree; b++) {
                    int ii = i + a, jj = j + b;
                    if (ii < 0 || ii >= H || jj < 0 || jj >= W || a * a + b * b > R * R) continue;
                    for (int k = head[(size_t)ii * W + jj]; k >= 0 && !agree; k = next[k])
                        agree = isnan(along[k]) || fabs(sin(line - along[k])) <= tolerance;
                }
            if (!agree) edge[p] = 0;
        }
    free(head);
    free(next);
    free(along);
    return WS_OK;
}

int ws_edge_consensus_line_target(const ws_edge_consensus *c, const ws_view *v, const ws_silhouette *band,
                                  float *edge, ws_status *st) {
    const int W = v->cam.width, H = v->cam.height;
    const size_t hw = (size_t)W * H;
    /* a wire's hull: a tube a few cubes across that stands a cube proud of
     * the wire all round, so its rim is left out (edge_consensus.h) */
    const int wire = wire_hull(c);
    float *near = ws_malloc(hw * sizeof *near, "edge consensus", st);
    float *beyond = near && c->hull.occupied ? ws_malloc(hw * sizeof *beyond, "edge consensus", st) : NULL;
    uint8_t *set = beyond ? ws_malloc(hw, "edge consensus", st) : NULL;
    int rc = near && (!c->hull.occupied || set) ? WS_OK : st->code;
    if (!rc) rc = ws_edge_consensus_near(c, &v->cam, near, st);
    ws_image mask = {0};
    ws_silhouette sil = {0};
    if (!rc && c->hull.occupied && !(rc = ws_image_alloc(&mask, W, H, 1, st)))
        rc = hull_mask(c, &v->cam, mask.data, st);
    /* beyond: the distance to M; then a wire's M less its rim */
    if (!rc && beyond) {
        for (size_t p = 0; p < hw; p++) set[p] = mask.data[p] > 0.5f;
        rc = ws_distance_map(set, W, H, beyond, st);
    }
    if (!rc && wire) {
        for (size_t p = 0; p < hw; p++) set[p] = !set[p];
        rc = ws_distance_map(set, W, H, mask.data, st);
        for (size_t p = 0; !rc && p < hw; p++) mask.data[p] = mask.data[p] > WS_CONSENSUS_OUTSIDE_PX;
    }
    if (!rc && c->hull.occupied) rc = ws_silhouette_make(&v->photo, &mask, &sil, st);
    if (!rc) rc = ws_line_target(&v->photo, NULL, c->hull.occupied ? &sil : band, NULL, edge, st);
    if (!rc)
        for (size_t p = 0; p < hw; p++)
            if (!(near[p] <= WS_CONSENSUS_KEEP_PX) || (beyond && beyond[p] > WS_CONSENSUS_OUTSIDE_PX)) edge[p] = 0;
    if (!rc) rc = orientation_filter(c, v, edge, st);
    ws_image_free(&mask);
    ws_silhouette_free(&sil);
    free(near);
    free(beyond);
    free(set);
    return rc;
}
