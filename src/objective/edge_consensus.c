/* edge_consensus.c: the edges the views agree on inside the region of
 * interest (see edge_consensus.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "objective/edge_consensus.h"
#include "objective/line_target.h"
#include "render/distance.h"
#include "render/thin_edges.h"

/* dist (n views x H x W): D_v of every train view. */
static int edge_distances(const ws_split *train, float *dist, ws_status *st) {
    const int W = train->views[0].photo.width, H = train->views[0].photo.height;
    const size_t hw = (size_t)W * H;
    float *edge = ws_malloc(hw * sizeof *edge, "edge consensus", st);
    uint8_t *set = edge ? ws_malloc(hw, "edge consensus", st) : NULL;
    int rc = set ? WS_OK : st->code;
    for (int v = 0; v < train->n && !rc; v++) {
        const ws_image *photo = &train->views[v].photo;
        if (photo->width != W || photo->height != H) {
            rc = ws_fail(st, WS_EINTERNAL, "edge consensus: view %d is %d x %d, view 0 %d x %d", v, photo->width,
                         photo->height, W, H);
            break;
        }
        if (!(rc = ws_thin_edges(photo->data, W, H, edge, st))) {
            for (size_t p = 0; p < hw; p++) set[p] = edge[p] >= 0.5f;
            rc = ws_distance_map(set, W, H, dist + v * hw, st);
        }
    }
    free(edge);
    free(set);
    return rc;
}

#define WORDS ((WS_CONSENSUS_MAX_VIEWS + 63) / 64)
#define CAPS 26

/* What the votes read (edge_consensus.h). */
typedef struct {
    const ws_split *train;
    int nviews;
    const float *dist;
    double rho;               /* a grid cube's circumscribed radius */
    uint64_t cap[CAPS][WORDS]; /* the views of each cap, one bit each */
} votes;

/* x->cap: the views whose direction from centre lies within
 * WS_CONSENSUS_CAP_ANGLE of each of the 26 directions from a cube's centre
 * to its neighbours'. */
static void view_caps(votes *x, const double centre[3]) {
    memset(x->cap, 0, sizeof x->cap);
    const double cosine = cos(WS_CONSENSUS_CAP_ANGLE * M_PI / 180);
    int k = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                if (!dx && !dy && !dz) continue;
                for (int v = 0; v < x->nviews; v++) {
                    double pos[3];
                    ws_camera_position(&x->train->views[v].cam, pos);
                    double e[3] = {pos[0] - centre[0], pos[1] - centre[1], pos[2] - centre[2]};
                    double len = sqrt((dx * dx + dy * dy + dz * dz) * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]));
                    if (dx * e[0] + dy * e[1] + dz * e[2] > cosine * len) x->cap[k][v / 64] |= 1ull << (v % 64);
                }
                k++;
            }
}

/* 2 where grid point p is strong, 1 where it is weak, else 0
 * (edge_consensus.h). */
static uint8_t vote(const votes *x, const double p[3]) {
    uint64_t seen[WORDS] = {0}, hit[WORDS] = {0};
    for (int v = 0; v < x->nviews; v++) {
        const ws_camera *cam = &x->train->views[v].cam;
        double c[3], u, w;
        ws_camera_to_cam(cam, p, c);
        double d = ws_camera_project(cam, c, &u, &w);
        if (!(d > x->rho) || !(u >= 0 && u < cam->width && w >= 0 && w < cam->height)) continue;
        seen[v / 64] |= 1ull << (v % 64);
        float at = x->dist[((size_t)v * cam->height + (size_t)w) * cam->width + (size_t)u];
        if (at <= WS_CONSENSUS_VOTE_PX + cam->focal * x->rho / (2 * d)) hit[v / 64] |= 1ull << (v % 64);
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

/* Keeps the 26-connected parts of keep (n[0] x n[1] x n[2]; 0 = out, 1 =
 * weak, 2 = strong) that hold at least min_part strong points, as 1; the
 * rest 0. stack: as many longs as keep has points; a part's points are
 * kept at its far end while its flood fill uses the near end (3 = reached). */
static void keep_parts(uint8_t *keep, const int n[3], long min_part, long *stack) {
    const long total = (long)n[0] * n[1] * n[2];
    for (long start = 0; start < total; start++) {
        if (keep[start] != 1 && keep[start] != 2) continue;
        long top = 0, count = 0, strong = 0;
        stack[top++] = start;
        strong += keep[start] == 2;
        keep[start] = 3;
        while (top > 0) {
            long k = stack[--top];
            stack[total - 1 - count++] = k;
            int x = (int)(k % n[0]), y = (int)(k / n[0] % n[1]), z = (int)(k / ((long)n[0] * n[1]));
            for (int dz = -1; dz <= 1; dz++)
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int xx = x + dx, yy = y + dy, zz = z + dz;
                        if (xx < 0 || xx >= n[0] || yy < 0 || yy >= n[1] || zz < 0 || zz >= n[2]) continue;
                        long q = ((long)zz * n[1] + yy) * n[0] + xx;
                        if (keep[q] != 1 && keep[q] != 2) continue;
                        strong += keep[q] == 2;
                        keep[q] = 3;
                        stack[top++] = q;
                    }
        }
        uint8_t mark = strong >= min_part ? 4 : 0;
        for (long c = 0; c < count; c++) keep[stack[total - 1 - c]] = mark;
    }
    for (long k = 0; k < total; k++) keep[k] = keep[k] == 4;
}

int ws_edge_consensus_make(const ws_scene *scene, const ws_roi *roi, int resolution, ws_edge_consensus *c,
                           ws_status *st) {
    memset(c, 0, sizeof *c);
    c->roi = *roi;
    const ws_split *train = &scene->split[WS_TRAIN];
    double side = 0;
    for (int a = 0; a < 3; a++) side = fmax(side, roi->hi[a] - roi->lo[a]);
    c->voxel = side / resolution;
    int n[3];
    for (int a = 0; a < 3; a++) n[a] = (int)fmax(1, ceil((roi->hi[a] - roi->lo[a]) / c->voxel - 1e-9));
    c->tested = (long)n[0] * n[1] * n[2];
    const size_t hw = (size_t)scene->width * scene->height;
    float *dist = ws_malloc(hw * (size_t)(train->n ? train->n : 1) * sizeof *dist, "edge consensus", st);
    uint8_t *keep = dist ? ws_calloc((size_t)c->tested, 1, "edge consensus", st) : NULL;
    int rc = keep ? WS_OK : st->code;
    if (!rc && train->n) rc = edge_distances(train, dist, st);
    votes *x = rc ? NULL : ws_malloc(sizeof *x, "edge consensus", st);
    long *stack = x ? ws_malloc(sizeof *stack * (size_t)c->tested, "edge consensus", st) : NULL;
    if (!rc && !stack) rc = st->code;
    if (!rc) {
        *x = (votes){train, train->n < WS_CONSENSUS_MAX_VIEWS ? train->n : WS_CONSENSUS_MAX_VIEWS, dist,
                     c->voxel * sqrt(3.0) / 2, {{0}}};
        double centre[3];
        for (int a = 0; a < 3; a++) centre[a] = (roi->lo[a] + roi->hi[a]) / 2;
        view_caps(x, centre);
#pragma omp parallel for schedule(dynamic)
        for (int z = 0; z < n[2]; z++)
            for (int y = 0; y < n[1]; y++)
                for (int i = 0; i < n[0]; i++) {
                    double p[3] = {roi->lo[0] + (i + 0.5) * c->voxel, roi->lo[1] + (y + 0.5) * c->voxel,
                                   roi->lo[2] + (z + 0.5) * c->voxel};
                    keep[((size_t)z * n[1] + y) * n[0] + i] = vote(x, p);
                }
        keep_parts(keep, n, WS_CONSENSUS_MIN_PART, stack);
    }
    free(x);
    free(stack);
    if (!rc) {
        for (long k = 0; k < c->tested; k++) c->n += keep[k];
        c->p = ws_malloc(sizeof *c->p * 3 * (size_t)(c->n ? c->n : 1), "edge consensus", st);
        if (!c->p) rc = st->code;
    }
    if (!rc) {
        int m = 0;
        for (long k = 0; k < c->tested; k++) {
            if (!keep[k]) continue;
            long x = k % n[0], y = k / n[0] % n[1], z = k / ((long)n[0] * n[1]);
            c->p[3 * m] = roi->lo[0] + (x + 0.5) * c->voxel;
            c->p[3 * m + 1] = roi->lo[1] + (y + 0.5) * c->voxel;
            c->p[3 * m + 2] = roi->lo[2] + (z + 0.5) * c->voxel;
            m++;
        }
    }
    free(dist);
    free(keep);
    if (rc) ws_edge_consensus_free(c);
    return rc;
}

void ws_edge_consensus_free(ws_edge_consensus *c) {
    free(c->p);
    c->p = NULL;
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

int ws_edge_consensus_silhouette(const ws_edge_consensus *c, const ws_view *v, ws_silhouette *s, ws_status *st) {
    const ws_camera *cam = &v->cam;
    ws_image mask = {0};
    if (ws_image_alloc(&mask, cam->width, cam->height, 1, st)) return st->code;
    int rc = ws_edge_consensus_near(c, cam, mask.data, st);
    if (!rc) {
        for (size_t p = 0; p < (size_t)cam->width * cam->height; p++)
            mask.data[p] = mask.data[p] <= WS_CONSENSUS_SILHOUETTE_PX ? 1.0f : 0.0f;
        rc = ws_silhouette_make(&v->photo, &mask, s, st);
        /* the kept points are all there is of the object: a view says
         * what lies beyond its frame too (a band cut by the frame's edge
         * would leave the hull unbounded there) */
        if (!rc) s->touches_border = 0;
    }
    ws_image_free(&mask);
    return rc;
}

int ws_edge_consensus_line_target(const ws_edge_consensus *c, const ws_view *v, const ws_silhouette *sil,
                                  float *edge, ws_status *st) {
    const size_t hw = (size_t)v->cam.width * v->cam.height;
    float *near = ws_malloc(hw * sizeof *near, "edge consensus", st);
    int rc = near ? WS_OK : st->code;
    if (!rc) rc = ws_edge_consensus_near(c, &v->cam, near, st);
    if (!rc) rc = ws_line_target(&v->photo, NULL, sil, NULL, edge, st);
    if (!rc)
        for (size_t p = 0; p < hw; p++)
            if (!(near[p] <= WS_CONSENSUS_KEEP_PX)) edge[p] = 0;
    free(near);
    return rc;
}
