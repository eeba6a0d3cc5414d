/* gt_coverage.c: the ground truth's coverage of the silhouettes (see
 * gt_coverage.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>
#include "render/distance.h"
#include "geometry/gt_coverage.h"
#include "geometry/hull.h"
#include "metrics/nearest.h"
#include "base/sort.h"

/* The spacing is measured on every SPACING_EVERY-th point (at least
 * SPACING_QUERIES of them where the cloud has that many) against the
 * cloud without them: leaving out one point in SPACING_EVERY or fewer
 * changes a point's nearest neighbour rarely enough that the median stays. */
#define SPACING_EVERY 8
#define SPACING_QUERIES 4096

static int median_spacing(const ws_pointcloud *gt, double *spacing, ws_status *st) {
    *spacing = 0;
    if (gt->n < 2) return WS_OK;
    int every = gt->n / SPACING_QUERIES > SPACING_EVERY ? gt->n / SPACING_QUERIES : SPACING_EVERY;
    int nq = (gt->n + every - 1) / every, nr = gt->n - nq;
    double *q = ws_malloc(sizeof *q * 3 * nq, "spacing queries", st);
    double *rest = q ? ws_malloc(sizeof *rest * 3 * nr, "spacing points", st) : NULL;
    double *dist = rest ? ws_malloc(sizeof *dist * nq, "spacing distances", st) : NULL;
    int rc = dist ? WS_OK : st->code;
    ws_nearest tree = {0};
    if (!rc) {
        for (int i = 0, a = 0, b = 0; i < gt->n; i++)
            memcpy(i % every ? &rest[3 * b++] : &q[3 * a++], &gt->xyz[3 * i], 3 * sizeof(double));
        rc = ws_nearest_build(&tree, rest, nr, st);
    }
    if (!rc) {
        ws_nearest_query(&tree, q, nq, dist, NULL);
        ws_sort_doubles(dist, (size_t)nq);
        *spacing = dist[nq / 2];
    }
    ws_nearest_free(&tree);
    free(q);
    free(rest);
    free(dist);
    return rc;
}

/* covered (H x W): 1 where the view sees a point (gt_coverage.h): the
 * pixels the points fall in are marked, and a pixel is covered when its
 * distance to a marked one (distance, H x W, scratch) is at most the disc
 * radius of the view's nearest point. One distance transform instead of a
 * disc per point: its cost does not grow with the points (docs/RESULTS.md,
 * "Numbers behind the code's constants"). */
static int draw_points(const ws_camera *cam, const ws_pointcloud *gt, double ball, uint8_t *covered, float *distance,
                       ws_status *st) {
    const int W = cam->width, H = cam->height;
    const size_t npix = (size_t)W * H;
    double nearest = INFINITY;
    memset(covered, 0, npix);
    for (int p = 0; p < gt->n; p++) {
        double c[3], u, w;
        ws_camera_to_cam(cam, &gt->xyz[3 * p], c);
        double d = ws_camera_project(cam, c, &u, &w);
        if (!(d > 0) || !(u >= 0 && u < W && w >= 0 && w < H)) continue;
        covered[(size_t)w * W + (size_t)u] = 1;
        nearest = fmin(nearest, d);
    }
    if (ws_distance_map(covered, W, H, distance, st)) return st->code;
    const double r = cam->focal * ball / nearest + WS_GT_SLACK;
    for (size_t i = 0; i < npix; i++) covered[i] = distance[i] <= r;
    return WS_OK;
}

/* The uncovered fraction of each of split s's views into f; covered
 * (n x H x W) keeps each view's discs; distance: a scratch map of the
 * largest view per thread. */
static int measure_split(const ws_split *sp, const ws_silhouette *sil, const ws_pointcloud *gt, double ball,
                         uint8_t *covered, float *distance, size_t most, double *f, ws_gt_coverage_split *c,
                         ws_status *st) {
    int failed = -1;
    #pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < sp->n; k++) {
        const ws_camera *cam = &sp->views[k].cam;
        const size_t npix = (size_t)cam->width * cam->height;
        uint8_t *mine = covered + (size_t)k * npix;
        ws_status own;
        ws_status_clear(&own);
        if (draw_points(cam, gt, ball, mine, distance + most * omp_get_thread_num(), &own)) {
            #pragma omp critical(gt_coverage_failed)
            if (failed < 0 || k < failed) failed = k, *st = own;
            continue;
        }
        long missed = 0;
        for (size_t i = 0; i < npix; i++) missed += sil[k].in[i] && !mine[i];
        f[k] = sil[k].area ? (double)missed / sil[k].area : 0;
    }
    if (failed >= 0) return st->code;
    *c = (ws_gt_coverage_split){.n = sp->n, .worst_view = 0};
    for (int k = 0; k < sp->n; k++) {
        c->mean += f[k] / sp->n;
        if (f[k] > c->worst) c->worst = f[k], c->worst_view = k;
    }
    return WS_OK;
}

/* Marks in `region` the hull voxels uncovered in most views that see them
 * (gt_coverage.h); returns their number. */
static long find_region(const ws_split *sp, const ws_silhouette *sil, const uint8_t *covered, const ws_hull *h,
                        uint8_t *region) {
    long count = 0;
    #pragma omp parallel for schedule(dynamic, 1) reduction(+ : count)
    for (int z = 0; z < h->n[2]; z++)
        for (int y = 0; y < h->n[1]; y++)
            for (int x = 0; x < h->n[0]; x++) {
                size_t v = ws_hull_index(h, x, y, z);
                region[v] = 0;
                if (!ws_hull_in(h, v)) continue;
                double p[3], c[3], u, w;
                ws_hull_voxel_center(h, x, y, z, p);
                int seen = 0, missed = 0;
                for (int k = 0; k < sp->n; k++) {
                    const ws_camera *cam = &sp->views[k].cam;
                    ws_camera_to_cam(cam, p, c);
                    if (!(ws_camera_project(cam, c, &u, &w) > 0)) continue;
                    double j = floor(u), i = floor(w);
                    if (j < 0 || i < 0 || j >= cam->width || i >= cam->height) continue;
                    size_t at = (size_t)i * cam->width + (size_t)j;
                    if (!sil[k].in[at]) continue;
                    seen++;
                    missed += !covered[(size_t)k * cam->width * cam->height + at];
                }
                region[v] = 4 * seen >= sp->n && 2 * missed > seen;
                count += region[v];
            }
    return count;
}

/* The centroid and box of the region's voxels (in voxel order, so that the
 * sums do not depend on the thread count). */
static void locate_region(const ws_hull *h, const uint8_t *region, ws_gt_coverage *c) {
    double sum[3] = {0, 0, 0};
    long n = 0;
    for (int a = 0; a < 3; a++) c->lo[a] = INFINITY, c->hi[a] = -INFINITY;
    for (int z = 0; z < h->n[2]; z++)
        for (int y = 0; y < h->n[1]; y++)
            for (int x = 0; x < h->n[0]; x++) {
                if (!region[ws_hull_index(h, x, y, z)]) continue;
                double p[3];
                ws_hull_voxel_center(h, x, y, z, p);
                for (int a = 0; a < 3; a++) {
                    sum[a] += p[a];
                    c->lo[a] = fmin(c->lo[a], p[a]);
                    c->hi[a] = fmax(c->hi[a], p[a]);
                }
                n++;
            }
    for (int a = 0; a < 3; a++) c->centroid[a] = n ? sum[a] / n : NAN;
}

int ws_gt_coverage_measure(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS],
                           const ws_pointcloud *gt, double tube, const char *path, int resolution,
                           ws_gt_coverage *c, ws_status *st) {
    memset(c, 0, sizeof *c);
    c->reference = -1;
    for (int s = 0; s < WS_NSPLITS; s++)
        if (scene->split[s].n > 0 && (c->reference < 0 || scene->split[s].n > scene->split[c->reference].n))
            c->reference = s;
    if (c->reference < 0) return WS_OK;
    int rc = median_spacing(gt, &c->spacing, st);
    c->ball = WS_GT_DISC_SPACINGS * c->spacing + tube;
    size_t most = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            const ws_camera *cam = &scene->split[s].views[k].cam;
            size_t npix = (size_t)cam->width * cam->height;
            most = most > npix ? most : npix;
        }
    const ws_split *ref = &scene->split[c->reference];
    uint8_t *covered = rc ? NULL : ws_malloc(most * ref->n, "ground-truth discs", st);
    int threads = 1;
    #pragma omp parallel
    #pragma omp single
    threads = omp_get_num_threads();
    float *distance = covered ? ws_malloc(sizeof *distance * most * threads, "ground-truth distances", st) : NULL;
    double *f = distance ? ws_malloc(sizeof *f * ref->n, "uncovered fractions", st) : NULL;
    ws_hull_view *hv = f ? ws_malloc(sizeof *hv * ref->n, "hull views", st) : NULL;
    if (!hv) rc = st->code;
    /* The reference split last, so that `covered` keeps its discs. */
    for (int t = 0; t <= WS_NSPLITS && !rc; t++) {
        int s = t < WS_NSPLITS ? t : c->reference;
        if (s == c->reference && t < WS_NSPLITS) continue;
        rc = measure_split(&scene->split[s], sil[s], gt, c->ball, covered, distance, most, f, &c->split[s], st);
    }
    ws_hull h = {0};
    for (int k = 0; k < ref->n && !rc; k++)
        hv[k] = (ws_hull_view){.cam = &ref->views[k].cam, .sil = &sil[c->reference][k]};
    if (!rc)
        rc = ws_hull_carve(hv, ref->n, scene->center, resolution, ws_hull_default_tolerance(ref->n), 0, &h, st);
    uint8_t *region = rc ? NULL : ws_malloc((size_t)h.n[0] * h.n[1] * h.n[2], "uncovered voxels", st);
    if (!rc && !region) rc = st->code;
    if (!rc) {
        c->region_voxels = find_region(ref, sil[c->reference], covered, &h, region);
        locate_region(&h, region, c);
        c->flagged = c->split[c->reference].mean >= WS_GT_UNCOVERED_FLAG && c->region_voxels >= WS_GT_REGION_VOXELS;
    }
    if (c->flagged)
        snprintf(c->line, sizeof c->line,
                 "%s: the ground truth misses part of the object every photo shows: about %.1f%% of the "
                 "silhouettes, around (%.2f, %.2f, %.2f) (extent %.2f x %.2f x %.2f); surface distances there "
                 "measure the ground truth, not the sketch",
                 path, 100 * c->split[c->reference].mean, c->centroid[0], c->centroid[1], c->centroid[2],
                 c->hi[0] - c->lo[0] + h.voxel, c->hi[1] - c->lo[1] + h.voxel, c->hi[2] - c->lo[2] + h.voxel);
    ws_hull_free(&h);
    free(region);
    free(hv);
    free(f);
    free(distance);
    free(covered);
    return rc;
}
