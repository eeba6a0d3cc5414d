/* photo_hull.c: space carving of the region of interest (see photo_hull.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "geometry/photo_hull.h"
#include "geometry/view_spread.h"
#include "base/progress.h"

static size_t cube_index(const ws_photo_hull *h, int x, int y, int z) {
    return ((size_t)z * h->n[1] + y) * h->n[0] + x;
}

static int occupied_at(const ws_photo_hull *h, int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= h->n[0] || y >= h->n[1] || z >= h->n[2]) return 0;
    return h->occupied[cube_index(h, x, y, z)];
}

/* Occupied with an empty or outside 6-neighbour. */
static int on_surface(const ws_photo_hull *h, int x, int y, int z) {
    return occupied_at(h, x, y, z) &&
           (!occupied_at(h, x - 1, y, z) || !occupied_at(h, x + 1, y, z) || !occupied_at(h, x, y - 1, z) ||
            !occupied_at(h, x, y + 1, z) || !occupied_at(h, x, y, z - 1) || !occupied_at(h, x, y, z + 1));
}

/* The surface cubes' indices, in grid order; returns how many. */
static long list_surface(const ws_photo_hull *h, long *surface) {
    long n = 0;
    for (int z = 0; z < h->n[2]; z++)
        for (int y = 0; y < h->n[1]; y++)
            for (int x = 0; x < h->n[0]; x++)
                if (on_surface(h, x, y, z)) surface[n++] = (long)cube_index(h, x, y, z);
    return n;
}

/* Where cube i lands in cam: its centre's image point (u, v), depth d and
 * the half-side in pixels of its square; 0 when it is behind the camera. */
static int cube_footprint(const ws_photo_hull *h, long i, const ws_camera *cam, double *u, double *v, double *d,
                          double *half) {
    const int x = (int)(i % h->n[0]), y = (int)(i / h->n[0] % h->n[1]), z = (int)(i / h->n[0] / h->n[1]);
    const double p[3] = {h->lo[0] + (x + 0.5) * h->voxel, h->lo[1] + (y + 0.5) * h->voxel,
                         h->lo[2] + (z + 0.5) * h->voxel};
    double c[3];
    ws_camera_to_cam(cam, p, c);
    *d = ws_camera_project(cam, c, u, v);
    if (!(*d > 1e-9)) return 0;
    *half = WS_PHOTO_HULL_SPLAT * cam->focal * h->voxel / *d;
    return 1;
}

/* depth (H x W): the nearest of the listed cubes over each pixel, INFINITY
 * where none; cover (H x W): 1 there, else 0; either may be NULL. A cube
 * covers the pixels whose centres its square holds, and always the one its
 * centre falls in. */
static void splat_cubes(const ws_photo_hull *h, const long *cubes, long n, const ws_camera *cam, float *depth,
                        float *cover) {
    const int W = cam->width, H = cam->height;
    for (size_t p = 0; p < (size_t)W * H; p++) {
        if (depth) depth[p] = INFINITY;
        if (cover) cover[p] = 0;
    }
    for (long k = 0; k < n; k++) {
        double u, v, d, half;
        if (!cube_footprint(h, cubes[k], cam, &u, &v, &d, &half)) continue;
        const int col = (int)floor(u), row = (int)floor(v);
        const int i0 = (int)fmin(row, ceil(v - half - 0.5)), i1 = (int)fmax(row, floor(v + half - 0.5));
        const int j0 = (int)fmin(col, ceil(u - half - 0.5)), j1 = (int)fmax(col, floor(u + half - 0.5));
        for (int i = i0 < 0 ? 0 : i0; i <= i1 && i < H; i++)
            for (int j = j0 < 0 ? 0 : j0; j <= j1 && j < W; j++) {
                const size_t p = (size_t)i * W + j;
                if (cover) cover[p] = 1;
                if (depth && d < depth[p]) depth[p] = (float)d;
            }
    }
}

/* What a carving pass reads: the views, their depth maps, and for each
 * view the others at least WS_PHOTO_HULL_PAIR_DEG away, nearest first,
 * with the direction (tangent to the sphere of views) towards each. */
typedef struct {
    const ws_view **views; /* nviews train views: all, or WS_PHOTO_HULL_VIEWS spread (view_spread.h) */
    int nviews;
    float **depth;   /* nviews maps of H x W */
    int *order;      /* nviews x nviews: view v's partners, nearest first */
    int *npartners;  /* nviews */
    double *towards; /* nviews x nviews x 3: unit tangent at v towards w */
} carving;

static int make_partners(carving *k, const double centre[3], ws_status *st) {
    const int n = k->nviews;
    double *dir = ws_malloc(sizeof *dir * 3 * (size_t)n, "photo hull", st), *angle = NULL;
    k->order = dir ? ws_malloc(sizeof *k->order * (size_t)n * n, "photo hull", st) : NULL;
    k->npartners = k->order ? ws_calloc((size_t)n, sizeof *k->npartners, "photo hull", st) : NULL;
    k->towards = k->npartners ? ws_malloc(sizeof *k->towards * 3 * (size_t)n * n, "photo hull", st) : NULL;
    angle = k->towards ? ws_malloc(sizeof *angle * (size_t)n, "photo hull", st) : NULL;
    if (!angle) {
        free(dir);
        return st->code;
    }
    for (int v = 0; v < n; v++) ws_view_direction(&k->views[v]->cam, centre, dir + 3 * v);
    for (int v = 0; v < n; v++) {
        int *o = k->order + (size_t)v * n, m = 0;
        for (int w = 0; w < n; w++) {
            const double *a = dir + 3 * v, *b = dir + 3 * w;
            const double c = fmax(-1, fmin(1, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]));
            double *t = k->towards + 3 * ((size_t)v * n + w), len = 0;
            for (int x = 0; x < 3; x++) t[x] = b[x] - c * a[x], len += t[x] * t[x];
            for (int x = 0; x < 3; x++) t[x] = len > 0 ? t[x] / sqrt(len) : 0;
            angle[w] = acos(c) * 180 / M_PI;
            if (w != v && angle[w] >= WS_PHOTO_HULL_PAIR_DEG) o[m++] = w;
        }
        for (int i = 1; i < m; i++) /* insertion sort by angle: stable, so ties stay in view order */
            for (int j = i; j > 0 && angle[o[j]] < angle[o[j - 1]]; j--) {
                const int t = o[j];
                o[j] = o[j - 1], o[j - 1] = t;
            }
        k->npartners[v] = m;
    }
    free(dir);
    free(angle);
    return WS_OK;
}

/* A view that sees a cube, and where: its centre's pixel and the
 * half-side of the footprint the samples come from. */
typedef struct {
    int view, col, row, radius;
} sighting;

/* How far the photo of sighting b comes, within its footprint, to colour
 * c: the least over its pixels of the largest channel difference, stopping
 * at the first within WS_PHOTO_HULL_TAU_FULL (which agrees fully anyway). */
static float footprint_distance(const carving *k, const sighting *b, const float c[3]) {
    const ws_image *photo = &k->views[b->view]->photo;
    const int W = photo->width, H = photo->height, r = b->radius;
    const size_t hw = (size_t)W * H;
    float nearest = INFINITY;
    for (int i = b->row - r < 0 ? 0 : b->row - r; i <= b->row + r && i < H; i++)
        for (int j = b->col - r < 0 ? 0 : b->col - r; j <= b->col + r && j < W; j++) {
            const float *q = photo->data + (size_t)i * W + j;
            const float d = fmaxf(fabsf(q[0] - c[0]), fmaxf(fabsf(q[hw] - c[1]), fabsf(q[2 * hw] - c[2])));
            if (d < nearest) nearest = d;
            if (nearest <= (float)WS_PHOTO_HULL_TAU_FULL) return nearest;
        }
    return nearest;
}

/* A pair's agreement (photo_hull.h): 1 up to WS_PHOTO_HULL_TAU_FULL, 0 from
 * WS_PHOTO_HULL_TAU_NONE, linear between. */
static double pair_agreement(const carving *k, const sighting *b, const float c[3]) {
    const double d = footprint_distance(k, b, c);
    return fmin(1, fmax(0, (WS_PHOTO_HULL_TAU_NONE - d) / (WS_PHOTO_HULL_TAU_NONE - WS_PHOTO_HULL_TAU_FULL)));
}

/* Whether the surface cube i agrees across the views that see it
 * (photo_hull.h). seen: scratch of nviews sightings; slot: of nviews ints. */
static int cube_agrees(const ws_photo_hull *h, long i, const carving *k, sighting *seen, int *slot) {
    const int W = k->views[0]->photo.width, H = k->views[0]->photo.height, n = k->nviews;
    int nseen = 0;
    for (int v = 0; v < n; v++) {
        double u, w, d, half;
        slot[v] = -1;
        if (!cube_footprint(h, i, &k->views[v]->cam, &u, &w, &d, &half)) continue;
        const int col = (int)floor(u), row = (int)floor(w);
        if (col < 0 || row < 0 || col >= W || row >= H) continue;
        if (!(d <= k->depth[v][(size_t)row * W + col] + WS_PHOTO_HULL_DEPTH_TOL * h->voxel)) continue;
        const int r = (int)lround(half);
        slot[v] = nseen;
        seen[nseen++] = (sighting){v, col, row, r < 1 ? 1 : r};
    }
    if (nseen < WS_PHOTO_HULL_MIN_VIEWS) return 1;
    double agree = 0;
    int pairs = 0;
    for (int s = 0; s < nseen; s++) {
        const int v = seen[s].view, *order = k->order + (size_t)v * n;
        const ws_image *photo = &k->views[v]->photo;
        const size_t hw = (size_t)photo->width * photo->height, at = (size_t)seen[s].row * photo->width + seen[s].col;
        const float c[3] = {photo->data[at], photo->data[hw + at], photo->data[2 * hw + at]};
        int first = -1, second = -1;
        for (int q = 0; q < k->npartners[v] && second < 0; q++) {
            const int t = slot[order[q]];
            if (t < 0) continue;
            if (first < 0) {
                first = t;
                continue;
            }
            const double *a = k->towards + 3 * ((size_t)v * n + seen[first].view);
            const double *b = k->towards + 3 * ((size_t)v * n + seen[t].view);
            if (fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) <= WS_PHOTO_HULL_CROSS) second = t;
        }
        if (first >= 0) pairs++, agree += pair_agreement(k, &seen[first], c);
        if (second >= 0) pairs++, agree += pair_agreement(k, &seen[second], c);
    }
    return pairs < WS_PHOTO_HULL_MIN_VIEWS || agree >= WS_PHOTO_HULL_AGREE * pairs;
}

long *ws_photo_hull_parts(const ws_photo_hull *h, const uint8_t *among, long *label, long *stack, long *nparts,
                          ws_status *st) {
    const size_t total = (size_t)h->n[0] * h->n[1] * h->n[2];
    long parts = 0, *size = NULL;
    for (size_t i = 0; i < total; i++) label[i] = h->occupied[i] && (!among || among[i]) ? (long)total : -1; /* total: not labelled yet */
    for (size_t seed = 0; seed < total; seed++) {
        if (label[seed] != (long)total) continue; /* not a member, or labelled already */
        if ((parts & (parts - 1)) == 0) { /* 0, 1, 2, 4, ...: full */
            long *grown = realloc(size, sizeof *grown * (size_t)(parts ? 2 * parts : 1));
            if (!grown) {
                free(size);
                ws_fail(st, WS_ENOMEM, "photo hull: out of memory");
                return NULL;
            }
            size = grown;
        }
        long top = 0, count = 0;
        stack[top++] = (long)seed;
        label[seed] = parts;
        while (top) {
            const long i = stack[--top];
            const int x = (int)(i % h->n[0]), y = (int)(i / h->n[0] % h->n[1]), z = (int)(i / h->n[0] / h->n[1]);
            count++;
            for (int dz = -1; dz <= 1; dz++)
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        if (!occupied_at(h, x + dx, y + dy, z + dz)) continue;
                        const size_t j = cube_index(h, x + dx, y + dy, z + dz);
                        if (label[j] != (long)total) continue;
                        label[j] = parts;
                        stack[top++] = (long)j;
                    }
        }
        size[parts++] = count;
    }
    *nparts = parts;
    if (!size && !(size = malloc(sizeof *size))) ws_fail(st, WS_ENOMEM, "photo hull: out of memory");
    return size;
}

/* Drops the 26-connected parts smaller than WS_PHOTO_HULL_PART of the
 * largest. label, stack: scratch of a long per cube. */
static int drop_flecks(ws_photo_hull *h, long *label, long *stack, ws_status *st) {
    const size_t total = (size_t)h->n[0] * h->n[1] * h->n[2];
    long parts, largest = 0, *size = ws_photo_hull_parts(h, NULL, label, stack, &parts, st);
    if (!size) return st->code;
    for (long k = 0; k < parts; k++) largest = size[k] > largest ? size[k] : largest;
    for (size_t i = 0; i < total; i++)
        if (h->occupied[i] && size[label[i]] < WS_PHOTO_HULL_PART * largest) h->occupied[i] = 0;
    free(size);
    return WS_OK;
}

/* Carving passes until one carves nothing (photo_hull.h). surface, carve:
 * scratch of a long per cube. */
static int carve_passes(ws_photo_hull *h, const carving *k, long *surface, long *carve, ws_progress *progress,
                        ws_status *st) {
    for (;;) {
        const long n = list_surface(h, surface);
        #pragma omp parallel for schedule(dynamic, 1)
        for (int v = 0; v < k->nviews; v++) splat_cubes(h, surface, n, &k->views[v]->cam, k->depth[v], NULL);
        int failed = 0;
        #pragma omp parallel
        {
            sighting *seen = malloc(sizeof *seen * (size_t)k->nviews);
            int *slot = malloc(sizeof *slot * (size_t)k->nviews);
            if (!seen || !slot) {
                #pragma omp atomic write
                failed = 1;
            }
            #pragma omp for schedule(dynamic, 256)
            for (long q = 0; q < n; q++) carve[q] = seen && slot && !cube_agrees(h, surface[q], k, seen, slot);
            free(seen);
            free(slot);
        }
        if (failed) return ws_fail(st, WS_ENOMEM, "photo hull: out of memory");
        long carved = 0;
        for (long q = 0; q < n; q++)
            if (carve[q]) h->occupied[surface[q]] = 0, carved++;
        h->passes++;
        ws_progress_advance(progress, 1);
        if (!carved) return WS_OK;
    }
}

int ws_photo_hull_make(const ws_scene *scene, const ws_roi *roi, int resolution, ws_photo_hull *h, ws_status *st) {
    memset(h, 0, sizeof *h);
    const ws_split *train = &scene->split[WS_TRAIN];
    carving k = {0};
    if (train->n == 0) return ws_fail(st, WS_EINTERNAL, "photo hull: no train views");
    double centre[3];
    ws_roi_centre(roi, centre);
    if (!(k.views = ws_malloc(sizeof *k.views * WS_PHOTO_HULL_VIEWS, "photo hull", st)) ||
        ws_view_spread(train, centre, WS_PHOTO_HULL_VIEWS, k.views, &k.nviews, st)) {
        free(k.views);
        return st->code;
    }
    double side = 0;
    for (int a = 0; a < 3; a++) side = fmax(side, roi->hi[a] - roi->lo[a]);
    h->voxel = side / resolution;
    for (int a = 0; a < 3; a++) {
        h->n[a] = (int)fmax(1, ceil((roi->hi[a] - roi->lo[a]) / h->voxel - 1e-9));
        h->lo[a] = roi->lo[a];
    }
    const size_t total = (size_t)h->n[0] * h->n[1] * h->n[2], hw = (size_t)scene->width * scene->height;
    h->occupied = ws_malloc(total, "photo hull", st);
    long *surface = h->occupied ? ws_malloc(total * sizeof *surface, "photo hull", st) : NULL;
    long *carve = surface ? ws_malloc(total * sizeof *carve, "photo hull", st) : NULL;
    k.depth = carve ? ws_calloc((size_t)k.nviews, sizeof *k.depth, "photo hull", st) : NULL;
    int rc = k.depth ? make_partners(&k, centre, st) : st->code;
    for (int v = 0; v < k.nviews && !rc; v++)
        if (!(k.depth[v] = ws_malloc(hw * sizeof **k.depth, "photo hull", st))) rc = st->code;
    if (!rc) {
        memset(h->occupied, 1, total);
        ws_progress_begin(scene->progress, "carving the photo hull", "passes", 0);
        rc = carve_passes(h, &k, surface, carve, scene->progress, st);
        ws_progress_end(scene->progress);
    }
    if (!rc) rc = drop_flecks(h, surface, carve, st);
    free(surface);
    if (!rc) rc = ws_photo_hull_update(h, st); /* what every projection splats: listed once */
    for (int v = 0; k.depth && v < k.nviews; v++) free(k.depth[v]);
    free(k.depth);
    free(k.views);
    free(k.order);
    free(k.npartners);
    free(k.towards);
    free(carve);
    if (rc) ws_photo_hull_free(h);
    return rc;
}

int ws_photo_hull_update(ws_photo_hull *h, ws_status *st) {
    const size_t total = (size_t)h->n[0] * h->n[1] * h->n[2];
    long *surface = ws_malloc(total * sizeof *surface, "photo hull", st);
    if (!surface) return st->code;
    h->kept = 0;
    for (size_t i = 0; i < total; i++) h->kept += h->occupied[i];
    free(h->surface);
    h->nsurface = list_surface(h, surface);
    long *fitted = realloc(surface, sizeof *surface * (size_t)(h->nsurface ? h->nsurface : 1));
    h->surface = fitted ? fitted : surface;
    return WS_OK;
}

void ws_photo_hull_free(ws_photo_hull *h) {
    free(h->occupied);
    free(h->surface);
    memset(h, 0, sizeof *h);
}

void ws_photo_hull_project(const ws_photo_hull *h, const ws_camera *cam, float *depth, float *mask) {
    splat_cubes(h, h->surface, h->nsurface, cam, depth, mask);
}
