/* respawn.c: moving idle curves (see respawn.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "fit/respawn.h"
#include "geometry/silhouette.h"
#include "geometry/surface.h"

#define PIXEL_SLACK 1.42

struct ws_respawn {
    const ws_split *train;
    ws_silhouette *sil;       /* one per training view */
    ws_hull_surface surface;
    double length;            /* of a respawned stroke */
};

int ws_respawn_create(ws_respawn **out, const ws_scene *scene, int n_curves, double length,
                      ws_status *st) {
    *out = NULL;
    ws_respawn *r = ws_calloc(1, sizeof *r, "respawn", st);
    if (!r) return st->code;
    r->train = &scene->split[WS_TRAIN];
    int rc = ws_split_silhouettes(r->train, &r->sil, st);
    if (!rc) rc = ws_scene_hull_surface(scene, WS_TRAIN, WS_HULL_INIT_RESOLUTION, &r->surface, st);
    /* The stroke length of the initial spread (surface.h), without its rng. */
    int k = n_curves < r->surface.n ? n_curves : r->surface.n, *picked = NULL;
    double spacing = 0;
    ws_rng none;
    ws_rng_seed(&none, 0);
    if (!rc && !(picked = ws_malloc(sizeof(int) * (k ? k : 1), "spread", st))) rc = st->code;
    if (!rc && k > 0) rc = ws_hull_surface_spread(&r->surface, NULL, 0, k, &none, picked, &spacing, st);
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
    ws_silhouettes_free(r->sil, r->train->n);
    ws_hull_surface_free(&r->surface);
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
        outside += s->distance[(size_t)(int)v * cam->width + (int)u] > reach + PIXEL_SLACK;
    }
    return 2 * outside > seen;
}

static int curve_idle(const ws_respawn *r, const ws_curves *c, const ws_gaussians *g, int first,
                      int count, const ws_adam *adam, int ci) {
    int moved_ever = 0;
    for (int x = 0; x < WS_CURVE_FLOATS; x++) moved_ever |= adam->v[ci * WS_CURVE_FLOATS + x] > 0;
    if (!moved_ever) return 1;
    int outside = 0;
    for (int k = first; k < first + count; k++) outside += gaussian_outside(r, g->mu + 3 * k, c->thickness);
    return 2 * outside > count;
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

int ws_respawn_step(ws_respawn *r, ws_curves *c, ws_adam *adam, int *moved, ws_status *st) {
    *moved = 0;
    ws_gaussians g = {0};
    if (ws_curves_sample(c, &g, st)) return st->code;
    int *idle = ws_calloc(c->n, sizeof *idle, "idle curves", st);
    int *first = idle ? ws_calloc((size_t)c->n + 1, sizeof *first, "curve offsets", st) : NULL;
    double *keep = first ? ws_malloc(sizeof(double) * 3 * ((size_t)g.n + c->n), "kept centres", st) : NULL;
    if (!keep) {
        free(idle);
        free(first);
        ws_gaussians_free(&g);
        return st->code;
    }
    for (int k = 0; k < g.n; k++) first[g.curve[k] + 1]++;
    for (int ci = 0; ci < c->n; ci++) first[ci + 1] += first[ci];
    #pragma omp parallel for schedule(dynamic, 1)
    for (int ci = 0; ci < c->n; ci++)
        idle[ci] = curve_idle(r, c, &g, first[ci], first[ci + 1] - first[ci], adam, ci);
    int nkeep = 0;
    for (int k = 0; k < g.n; k++)
        if (!idle[g.curve[k]]) memcpy(keep + 3 * nkeep++, g.mu + 3 * k, sizeof(double) * 3);
    int rc = WS_OK;
    for (int ci = 0; ci < c->n && !rc; ci++) {
        if (!idle[ci]) continue;
        int at;
        double spacing, dir[3];
        ws_rng unused; /* the spread draws only when nothing is kept */
        ws_rng_seed(&unused, (uint64_t)ci);
        rc = ws_hull_surface_spread(&r->surface, keep, nkeep, 1, &unused, &at, &spacing, st);
        if (rc) break;
        tangent(r->surface.normal + 3 * at, dir);
        ws_curve_set_segment(c, ci, r->surface.p + 3 * at, dir, r->length);
        memcpy(keep + 3 * nkeep++, r->surface.p + 3 * at, sizeof(double) * 3);
        memset(adam->m + (size_t)ci * WS_CURVE_FLOATS, 0, sizeof(double) * WS_CURVE_FLOATS);
        memset(adam->v + (size_t)ci * WS_CURVE_FLOATS, 0, sizeof(double) * WS_CURVE_FLOATS);
        ++*moved;
    }
    free(idle);
    free(first);
    free(keep);
    ws_gaussians_free(&g);
    return rc;
}
