/* surface.c: hull surfaces and the curves placed on them (see surface.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "geometry/surface.h"

static int in_hull(const ws_hull *h, int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= h->n[0] || y >= h->n[1] || z >= h->n[2]) return 0;
    return ws_hull_in(h, ws_hull_index(h, x, y, z));
}

static int on_surface(const ws_hull *h, int x, int y, int z) {
    return in_hull(h, x, y, z) && (!in_hull(h, x - 1, y, z) || !in_hull(h, x + 1, y, z) ||
                                   !in_hull(h, x, y - 1, z) || !in_hull(h, x, y + 1, z) ||
                                   !in_hull(h, x, y, z - 1) || !in_hull(h, x, y, z + 1));
}

/* The facing of point p with normal nv (see surface.h). */
static double facing(const double p[3], const double nv[3], const ws_hull_view *views, int nviews) {
    if (nv[0] == 0 && nv[1] == 0 && nv[2] == 0) return 1;
    double best = -1;
    for (int k = 0; k < nviews; k++) {
        const ws_camera *cam = views[k].cam;
        double c[3], u, v, pos[3], to[3], len = 0;
        ws_camera_to_cam(cam, p, c);
        if (!(ws_camera_project(cam, c, &u, &v) > 0) || !(u >= 0 && v >= 0 && u < cam->width && v < cam->height))
            continue;
        ws_camera_position(cam, pos);
        for (int a = 0; a < 3; a++) {
            to[a] = pos[a] - p[a];
            len += to[a] * to[a];
        }
        best = fmax(best, (to[0] * nv[0] + to[1] * nv[1] + to[2] * nv[2]) / sqrt(len));
    }
    return best;
}

int ws_hull_surface_make(const ws_hull *h, const ws_hull_view *views, int nviews, ws_hull_surface *s,
                         ws_status *st) {
    *s = (ws_hull_surface){0};
    long count = 0;
    for (int z = 0; z < h->n[2]; z++)
        for (int y = 0; y < h->n[1]; y++)
            for (int x = 0; x < h->n[0]; x++) count += on_surface(h, x, y, z);
    s->p = ws_malloc(sizeof(double) * 3 * (count ? count : 1), "hull surface", st);
    s->normal = s->p ? ws_malloc(sizeof(double) * 3 * (count ? count : 1), "hull surface", st) : NULL;
    s->facing = s->normal ? ws_malloc(sizeof(double) * (count ? count : 1), "hull surface", st) : NULL;
    if (!s->facing) {
        ws_hull_surface_free(s);
        return st->code;
    }
    for (int z = 0; z < h->n[2]; z++)
        for (int y = 0; y < h->n[1]; y++)
            for (int x = 0; x < h->n[0]; x++) {
                if (!on_surface(h, x, y, z)) continue;
                double *p = s->p + 3 * s->n, *nv = s->normal + 3 * s->n;
                ws_hull_voxel_center(h, x, y, z, p);
                nv[0] = nv[1] = nv[2] = 0;
                for (int dz = -1; dz <= 1; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++)
                            if (in_hull(h, x + dx, y + dy, z + dz)) {
                                nv[0] -= dx;
                                nv[1] -= dy;
                                nv[2] -= dz;
                            }
                double len = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
                for (int a = 0; a < 3; a++) nv[a] = len > 0.5 ? nv[a] / len : 0.0;
                s->facing[s->n] = facing(p, nv, views, nviews);
                s->placeable += s->facing[s->n] >= WS_SURFACE_MIN_FACING;
                s->n++;
            }
    return WS_OK;
}

void ws_hull_surface_free(ws_hull_surface *s) {
    free(s->p);
    free(s->normal);
    free(s->facing);
    *s = (ws_hull_surface){0};
}

int ws_scene_hull_make(const ws_scene *scene, int split, const ws_silhouette *sil, int resolution,
                       ws_scene_hull *out, ws_status *st) {
    const ws_split *sp = &scene->split[split];
    *out = (ws_scene_hull){0};
    ws_hull_view *hv = ws_malloc(sizeof *hv * (sp->n ? sp->n : 1), "hull views", st);
    int rc = hv ? WS_OK : st->code;
    for (int k = 0; k < sp->n && !rc; k++) hv[k] = (ws_hull_view){.cam = &sp->views[k].cam, .sil = &sil[k]};
    if (!rc)
        rc = ws_hull_carve(hv, sp->n, scene->center, resolution, ws_hull_default_tolerance(sp->n), 0, &out->hull, st);
    if (!rc) rc = ws_hull_surface_make(&out->hull, hv, sp->n, &out->surface, st);
    if (!rc && out->surface.n == 0)
        rc = ws_fail(st, WS_EINPUT, "%s: the %s views' silhouettes have no common volume (try "
                                    "`wiresketch check %s`)", scene->dir, ws_split_names[split], scene->dir);
    if (rc) ws_scene_hull_free(out);
    free(hv);
    return rc;
}

void ws_scene_hull_free(ws_scene_hull *h) {
    ws_hull_free(&h->hull);
    ws_hull_surface_free(&h->surface);
}

static double dist2(const double *a, const double *b) {
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

int ws_hull_surface_candidates(const ws_hull_surface *s) {
    return s->placeable > 0 ? s->placeable : s->n;
}

static int candidate(const ws_hull_surface *s, int i) {
    return s->placeable == 0 || s->facing[i] >= WS_SURFACE_MIN_FACING;
}

void ws_hull_surface_nearer(const ws_hull_surface *s, const double *points, int n, double *nearest) {
    #pragma omp parallel for schedule(static) if ((long)s->n * n > 20000)
    for (int i = 0; i < s->n; i++)
        for (int a = 0; a < n; a++) nearest[i] = fmin(nearest[i], dist2(s->p + 3 * i, points + 3 * a));
}

int ws_hull_surface_farthest(const ws_hull_surface *s, const double *nearest) {
    int best = -1;
    for (int i = 0; i < s->n; i++)
        if (candidate(s, i) && (best < 0 || nearest[i] > nearest[best])) best = i;
    return best;
}

int ws_hull_surface_spread(const ws_hull_surface *s, const double *avoid, int navoid, int k,
                           ws_rng *rng, int *picked, double *spacing, ws_status *st) {
    const int candidates = ws_hull_surface_candidates(s);
    if (k < 1 || k > candidates)
        return ws_fail(st, WS_EINTERNAL, "surface: %d points asked of %d", k, candidates);
    double *nearest = ws_malloc(sizeof(double) * s->n, "farthest-point distances", st);
    if (!nearest) return st->code;
    for (int i = 0; i < s->n; i++) nearest[i] = INFINITY;
    ws_hull_surface_nearer(s, avoid, navoid, nearest);
    *spacing = 0;
    for (int m = 0; m < k; m++) {
        int best = -1;
        if (m == 0 && navoid == 0) {
            do
                best = (int)ws_rng_below(rng, (uint64_t)s->n);
            while (!candidate(s, best));
        } else {
            best = ws_hull_surface_farthest(s, nearest);
            *spacing = sqrt(nearest[best]);
        }
        picked[m] = best;
        ws_hull_surface_nearer(s, s->p + 3 * best, 1, nearest);
    }
    free(nearest);
    return WS_OK;
}

int ws_curves_init_hull(ws_curves *c, const ws_hull_surface *s, int n, double length,
                        double thickness, double overlap, ws_rng *rng, ws_status *st) {
    /* Allocated and shaped by the random initialisation (which checks the
     * shape), then every curve moved onto the surface. */
    const double origin[3] = {0, 0, 0};
    if (ws_curves_init_random(c, n, origin, 0, 0, thickness, overlap, rng, st)) return st->code;
    int k = n < ws_hull_surface_candidates(s) ? n : ws_hull_surface_candidates(s);
    int *picked = ws_malloc(sizeof(int) * (k ? k : 1), "picked surface points", st);
    double spacing = 0;
    if (!picked || ws_hull_surface_spread(s, NULL, 0, k, rng, picked, &spacing, st)) {
        free(picked);
        ws_curves_free(c);
        return st->code;
    }
    for (int ci = 0; ci < n; ci++) {
        int at = picked[ci % k];
        double dir[3];
        ws_random_direction(rng, s->normal + 3 * at, dir);
        ws_curve_set_segment(c, ci, s->p + 3 * at, dir, fmax(length, 0.5 * spacing));
    }
    free(picked);
    return WS_OK;
}

void ws_hull_surface_depth(const ws_hull_surface *s, const ws_camera *cam, double rho, float *z, int *nearest,
                           float *far) {
    const int W = cam->width, H = cam->height;
    for (size_t p = 0; p < (size_t)W * H; p++) {
        z[p] = INFINITY;
        nearest[p] = -1;
        if (far) far[p] = -INFINITY;
    }
    for (int k = 0; k < s->n; k++) {
        double c[3], u, v;
        ws_camera_to_cam(cam, s->p + 3 * k, c);
        double d = ws_camera_project(cam, c, &u, &v);
        if (!(d > rho)) continue;
        double r = fmax(0.5, cam->focal * rho / d);
        /* pixel (i, j) when its centre (j + 1/2, i + 1/2) lies within r of (u, v) */
        int j0 = (int)fmax(0, ceil(u - r - WS_PIXEL_CENTER)), j1 = (int)fmin(W - 1, floor(u + r - WS_PIXEL_CENTER));
        int i0 = (int)fmax(0, ceil(v - r - WS_PIXEL_CENTER)), i1 = (int)fmin(H - 1, floor(v + r - WS_PIXEL_CENTER));
        for (int i = i0; i <= i1; i++)
            for (int j = j0; j <= j1; j++) {
                double dx = j + WS_PIXEL_CENTER - u, dy = i + WS_PIXEL_CENTER - v;
                size_t at = (size_t)i * W + j;
                if (dx * dx + dy * dy > r * r) continue;
                if (d < z[at]) {
                    z[at] = (float)d;
                    nearest[at] = k;
                }
                if (far && d > far[at]) far[at] = (float)d;
            }
    }
}
