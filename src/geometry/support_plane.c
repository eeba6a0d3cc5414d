/* support_plane.c: the support an object stands on, and the air over it
 * (see support_plane.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "base/sort.h"
#include "base/sym3.h"
#include "geometry/support_plane.h"

static int occupied_cell(const ws_photo_hull *h, long x, long y, long z) {
    if (x < 0 || y < 0 || z < 0 || x >= h->n[0] || y >= h->n[1] || z >= h->n[2]) return -1; /* outside */
    return h->occupied[((size_t)z * h->n[1] + y) * h->n[0] + x];
}

static void cube_centre(const ws_photo_hull *h, long i, double p[3]) {
    const long x = i % h->n[0], y = i / h->n[0] % h->n[1], z = i / ((long)h->n[0] * h->n[1]);
    p[0] = h->lo[0] + (x + 0.5) * h->voxel;
    p[1] = h->lo[1] + (y + 0.5) * h->voxel;
    p[2] = h->lo[2] + (z + 0.5) * h->voxel;
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Walks from p along dir (unit) in steps of half a cube until it enters a
 * cube whose centre's height along dir passes `until` (world units): that
 * cube's index, or WALK_EMPTY when an empty cube comes first, WALK_OUT when
 * the grid's side does. */
#define WALK_EMPTY (-1)
#define WALK_OUT (-2)
static long walk(const ws_photo_hull *h, const double p[3], const double dir[3], double until) {
    const double step = h->voxel / 2;
    for (int k = 1;; k++) {
        double q[3];
        for (int a = 0; a < 3; a++) q[a] = p[a] + k * step * dir[a];
        const long x = (long)floor((q[0] - h->lo[0]) / h->voxel), y = (long)floor((q[1] - h->lo[1]) / h->voxel),
                   z = (long)floor((q[2] - h->lo[2]) / h->voxel);
        const int o = occupied_cell(h, x, y, z);
        if (o < 0) return WALK_OUT;
        if (!o) return WALK_EMPTY;
        const long i = ((long)z * h->n[1] + y) * h->n[0] + x;
        double c[3];
        cube_centre(h, i, c);
        if (dot3(c, dir) > until) return i;
    }
}

/* The slice `WS_SUPPORT_LAYER` cubes thick across n that holds the most of
 * the tops (heights: their n . x); returns its count (-1 when out of
 * memory), its lowest height in *from. */
static long fullest_layer(const double *height, long ntops, double voxel, double *from, ws_status *st) {
    double lo = INFINITY, hi = -INFINITY;
    for (long i = 0; i < ntops; i++) lo = fmin(lo, height[i]), hi = fmax(hi, height[i]);
    const long bins = (long)((hi - lo) / voxel) + 1;
    long *count = ws_calloc((size_t)bins, sizeof *count, "support plane", st), best = 0;
    *from = lo;
    if (!count) return -1;
    for (long i = 0; i < ntops; i++) count[(long)((height[i] - lo) / voxel)]++;
    for (long b = 0; b < bins; b++) {
        long c = 0;
        for (long k = b; k < b + WS_SUPPORT_LAYER && k < bins; k++) c += count[k];
        if (c > best) best = c, *from = lo + b * voxel;
    }
    free(count);
    return best;
}

int ws_support_plane_find(const ws_photo_hull *h, const ws_split *train, ws_support_plane *s, ws_status *st) {
    memset(s, 0, sizeof *s);
    if (!h->occupied || h->nsurface == 0 || train->n == 0) return WS_OK;
    double centre[3], u[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++) centre[a] = h->lo[a] + h->n[a] * h->voxel / 2;
    for (int v = 0; v < train->n; v++) {
        double pos[3];
        ws_camera_position(&train->views[v].cam, pos);
        double e[3] = {pos[0] - centre[0], pos[1] - centre[1], pos[2] - centre[2]}, len = sqrt(dot3(e, e));
        for (int a = 0; len > 0 && a < 3; a++) u[a] += e[a] / len / train->n;
    }
    const double ulen = sqrt(dot3(u, u));
    if (!(ulen >= WS_SUPPORT_MIN_UP)) return WS_OK;
    for (int a = 0; a < 3; a++) u[a] /= ulen;
    const double down[3] = {-u[0], -u[1], -u[2]};
    const int step[3] = {(int)lround(u[0]), (int)lround(u[1]), (int)lround(u[2])};
    long *tops = ws_malloc(sizeof *tops * (size_t)h->nsurface, "support plane", st);
    double *height = tops ? ws_malloc(sizeof *height * (size_t)h->nsurface, "support plane", st) : NULL;
    if (!height) {
        free(tops);
        return st->code;
    }
    long ntops = 0;
    for (long k = 0; k < h->nsurface; k++) {
        const long i = h->surface[k], x = i % h->n[0], y = i / h->n[0] % h->n[1], z = i / ((long)h->n[0] * h->n[1]);
        if (occupied_cell(h, x + step[0], y + step[1], z + step[2]) != 0) continue;
        double p[3];
        cube_centre(h, i, p);
        if (walk(h, p, down, INFINITY) == WALK_OUT) tops[ntops++] = i; /* solid under it to the grid's side */
    }
    if (ntops < WS_SUPPORT_LAYER) { /* too few to fit a plane to: no support */
        free(tops), free(height);
        return WS_OK;
    }
    double n[3] = {u[0], u[1], u[2]}, from = 0;
    long layer = 0;
    for (int round = 0; round < 3; round++) {
        for (long k = 0; k < ntops; k++) {
            double p[3];
            cube_centre(h, tops[k], p);
            height[k] = dot3(n, p);
        }
        layer = fullest_layer(height, ntops, h->voxel, &from, st);
        if (layer < 0) {
            free(tops), free(height);
            return st->code;
        }
        if (round == 2) break;
        double mean[3] = {0, 0, 0}, m[6] = {0};
        long in = 0;
        for (long k = 0; k < ntops; k++) {
            if (height[k] < from || height[k] >= from + WS_SUPPORT_LAYER * h->voxel) continue;
            double p[3];
            cube_centre(h, tops[k], p);
            for (int a = 0; a < 3; a++) mean[a] += p[a];
            in++;
        }
        for (int a = 0; a < 3; a++) mean[a] /= in;
        for (long k = 0; k < ntops; k++) {
            if (height[k] < from || height[k] >= from + WS_SUPPORT_LAYER * h->voxel) continue;
            double p[3];
            cube_centre(h, tops[k], p);
            const double d[3] = {p[0] - mean[0], p[1] - mean[1], p[2] - mean[2]};
            m[0] += d[0] * d[0], m[1] += d[1] * d[1], m[2] += d[2] * d[2];
            m[3] += d[0] * d[1], m[4] += d[0] * d[2], m[5] += d[1] * d[2];
        }
        double t[3];
        ws_sym3_least_eigenvector(m, t);
        const double sign = dot3(t, u) < 0 ? -1 : 1;
        for (int a = 0; a < 3; a++) n[a] = sign * t[a];
    }
    /* the grid's cross-section across n, in cubes: its faces' areas times
     * the cosines */
    const double section = (double)h->n[1] * h->n[2] * fabs(n[0]) + (double)h->n[0] * h->n[2] * fabs(n[1]) +
                           (double)h->n[0] * h->n[1] * fabs(n[2]);
    memcpy(s->normal, n, sizeof n);
    const double mid = from + WS_SUPPORT_LAYER * h->voxel / 2, reach = WS_SUPPORT_REACH * h->voxel;
    long m = 0;
    for (long k = 0; k < ntops; k++)
        if (fabs(height[k] - mid) <= reach) height[m++] = height[k];
    s->share = section > 0 ? m / section : 0;
    /* the grid's extent across n, from its corners: an object standing on
     * the layer fills the region above it, so a layer in the upper part is
     * the ceiling of what too few or too small views could carve */
    double lowest = INFINITY, highest = -INFINITY;
    for (int corner = 0; corner < 8; corner++) {
        double q[3];
        for (int a = 0; a < 3; a++) q[a] = h->lo[a] + ((corner >> a) & 1) * h->n[a] * h->voxel;
        lowest = fmin(lowest, dot3(n, q)), highest = fmax(highest, dot3(n, q));
    }
    if (mid > lowest + WS_SUPPORT_LOWER * (highest - lowest)) s->share = 0;
    if (s->share >= WS_SUPPORT_SHARE) {
        ws_sort_doubles(height, (size_t)m);
        s->floor = height[(long)(WS_SUPPORT_LOW * (m - 1))];
        s->top = height[(long)(WS_SUPPORT_HIGH * (m - 1))];
    }
    free(tops);
    free(height);
    if (s->share < WS_SUPPORT_SHARE) return WS_OK;
    const size_t total = (size_t)h->n[0] * h->n[1] * h->n[2];
    s->foot = ws_calloc(total, 1, "support plane", st);
    if (!s->foot) return st->code;
    memcpy(s->n, h->n, sizeof s->n);
    memcpy(s->lo, h->lo, sizeof s->lo);
    s->voxel = h->voxel;
    const double above = s->top + WS_SUPPORT_MARGIN * h->voxel;
    /* the parts of the hull above the air: the object's, and what is left
     * of pillars of air */
    uint8_t *above_air = ws_malloc(total, "support plane", st);
    long *part = above_air ? ws_malloc(total * sizeof *part, "support plane", st) : NULL;
    long *stack = part ? ws_malloc(total * sizeof *stack, "support plane", st) : NULL, nparts = 0, *size = NULL;
    for (size_t i = 0; stack && i < total; i++) {
        double p[3];
        cube_centre(h, (long)i, p);
        above_air[i] = dot3(n, p) > above;
    }
    if (stack) size = ws_photo_hull_parts(h, above_air, part, stack, &nparts, st);
    free(above_air);
    if (!size) {
        free(part), free(stack);
        return st->code;
    }
    long largest = 0, feet = 0;
    for (long k = 0; k < nparts; k++) largest = size[k] > largest ? size[k] : largest;
    for (size_t i = 0; i < total; i++) {
        if (!h->occupied[i]) continue;
        double p[3];
        cube_centre(h, (long)i, p);
        const double z = dot3(n, p);
        if (z <= s->floor + h->voxel / 2 || z > above) continue;
        const long end = walk(h, p, n, above);
        if (end >= 0 && size[part[end]] >= WS_SUPPORT_PART * largest) s->foot[i] = 1, feet++;
    }
    free(size);
    /* the object stands above the layer's air, or the layer is no support
     * (a box's top face) */
    s->found = feet > 0;
    if (!s->found) {
        free(part), free(stack);
        free(s->foot);
        s->foot = NULL;
        return WS_OK;
    }
    /* each foot's reach: half its width, the square root of its cubes over
     * the slab's height in cubes */
    const ws_photo_hull feet_grid = {.voxel = h->voxel, .n = {h->n[0], h->n[1], h->n[2]}, .occupied = s->foot};
    long nfeet = 0, *foot_size = ws_photo_hull_parts(&feet_grid, NULL, part, stack, &nfeet, st);
    free(stack);
    if (!foot_size) {
        free(part);
        return st->code;
    }
    const double slab = (above - s->floor) / h->voxel;
    for (size_t i = 0; i < total; i++) {
        if (!s->foot[i]) continue;
        const long reach = lround(sqrt(foot_size[part[i]] / slab) / 2);
        s->foot[i] = (uint8_t)(reach < WS_SUPPORT_NEAR_MIN ? WS_SUPPORT_NEAR_MIN
                               : reach > WS_SUPPORT_NEAR   ? WS_SUPPORT_NEAR
                                                           : reach);
    }
    free(part);
    free(foot_size);
    return WS_OK;
}

int ws_support_plane_carve(ws_support_plane *s, ws_photo_hull *h, ws_status *st) {
    if (!s->found) return WS_OK;
    const size_t total = (size_t)h->n[0] * h->n[1] * h->n[2];
    const double above = s->top + WS_SUPPORT_MARGIN * h->voxel;
    for (size_t i = 0; i < total; i++) {
        if (!h->occupied[i] || s->foot[i]) continue;
        double p[3];
        cube_centre(h, (long)i, p);
        const double z = dot3(s->normal, p);
        if (z > s->floor + h->voxel / 2 && z <= above) h->occupied[i] = 0, s->carved++;
    }
    return ws_photo_hull_update(h, st);
}

int ws_support_plane_holds(const ws_support_plane *s, const double p[3]) {
    if (!s->found) return 0;
    if (dot3(s->normal, p) > s->top + WS_SUPPORT_MARGIN * s->voxel) return 0;
    const long c[3] = {(long)floor((p[0] - s->lo[0]) / s->voxel), (long)floor((p[1] - s->lo[1]) / s->voxel),
                       (long)floor((p[2] - s->lo[2]) / s->voxel)};
    const int r = WS_SUPPORT_NEAR;
    for (long z = c[2] - r; z <= c[2] + r; z++)
        for (long y = c[1] - r; y <= c[1] + r; y++)
            for (long x = c[0] - r; x <= c[0] + r; x++) {
                if (x < 0 || y < 0 || z < 0 || x >= s->n[0] || y >= s->n[1] || z >= s->n[2]) continue;
                const long across = labs(x - c[0]) > labs(y - c[1]) ? labs(x - c[0]) : labs(y - c[1]),
                           away = across > labs(z - c[2]) ? across : labs(z - c[2]); /* cubes, the largest axis's */
                const uint8_t reach = s->foot[((size_t)z * s->n[1] + y) * s->n[0] + x];
                if (reach && reach >= away) return 0;
            }
    return 1;
}

void ws_support_plane_free(ws_support_plane *s) {
    free(s->foot);
    memset(s, 0, sizeof *s);
}
