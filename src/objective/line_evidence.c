/* line_evidence.c: the hull's contours and creases seen from a view (see
 * line_evidence.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "objective/line_evidence.h"
#include "geometry/check.h"
#include "render/distance.h"

/* The surface variation lambda_0 / (lambda_0 + lambda_1 + lambda_2) of m
 * points with coordinate sums sum and sums of products sq (xx, yy, zz, xy,
 * xz, yz): lambda_0 the smallest eigenvalue of their covariance, found in
 * closed form (the trigonometric solution of the characteristic cubic). 0
 * on a plane, 1/3 for points spread evenly in every direction. */
static double surface_variation(const double sum[3], const double sq[6], int m) {
    double mean[3] = {sum[0] / m, sum[1] / m, sum[2] / m};
    double a = sq[0] / m - mean[0] * mean[0], b = sq[1] / m - mean[1] * mean[1], c = sq[2] / m - mean[2] * mean[2];
    double d = sq[3] / m - mean[0] * mean[1], e = sq[4] / m - mean[0] * mean[2], f = sq[5] / m - mean[1] * mean[2];
    double trace = a + b + c;
    if (!(trace > 0)) return 0;
    double q = trace / 3, p1 = d * d + e * e + f * f;
    double p2 = (a - q) * (a - q) + (b - q) * (b - q) + (c - q) * (c - q) + 2 * p1, p = sqrt(p2 / 6);
    if (!(p > 1e-12 * trace)) return 1.0 / 3; /* isotropic */
    double B[6] = {(a - q) / p, (b - q) / p, (c - q) / p, d / p, e / p, f / p};
    double det = B[0] * (B[1] * B[2] - B[5] * B[5]) - B[3] * (B[3] * B[2] - B[5] * B[4]) + B[4] * (B[3] * B[5] - B[1] * B[4]);
    double phi = acos(fmin(1, fmax(-1, det / 2))) / 3;
    double smallest = q + 2 * p * cos(phi + 2 * M_PI / 3);
    return fmax(0, smallest) / trace;
}

int ws_line_evidence_init(ws_line_evidence *e, const ws_scene_hull *hull, ws_status *st) {
    const ws_hull *h = &hull->hull;
    const ws_hull_surface *s = &hull->surface;
    e->hull = hull;
    e->crease = ws_calloc(s->n ? (size_t)s->n : 1, 1, "hull creases", st);
    size_t cells = (size_t)h->n[0] * h->n[1] * h->n[2];
    int *at = e->crease ? ws_malloc(cells * sizeof *at, "hull creases", st) : NULL;
    if (!at) {
        ws_line_evidence_free(e);
        return st->code;
    }
    /* the surface voxel of each grid cell (-1: none), by its centre */
    for (size_t c = 0; c < cells; c++) at[c] = -1;
    int (*cell)[3] = NULL;
    cell = ws_malloc((size_t)(s->n ? s->n : 1) * sizeof *cell, "hull creases", st);
    if (!cell) {
        free(at);
        ws_line_evidence_free(e);
        return st->code;
    }
    for (int k = 0; k < s->n; k++) {
        for (int x = 0; x < 3; x++) cell[k][x] = (int)floor((s->p[3 * k + x] - h->origin[x]) / h->voxel);
        if (cell[k][0] >= 0 && cell[k][0] < h->n[0] && cell[k][1] >= 0 && cell[k][1] < h->n[1] && cell[k][2] >= 0 &&
            cell[k][2] < h->n[2])
            at[ws_hull_index(h, cell[k][0], cell[k][1], cell[k][2])] = k;
    }
    const int r = WS_EVIDENCE_CREASE_REACH;
    const double limit = WS_EVIDENCE_CREASE_VARIATION;
#pragma omp parallel for schedule(static)
    for (int k = 0; k < s->n; k++) {
        double sum[3] = {0, 0, 0}, sq[6] = {0, 0, 0, 0, 0, 0};
        int m = 0;
        for (int dz = -r; dz <= r; dz++)
            for (int dy = -r; dy <= r; dy++)
                for (int dx = -r; dx <= r; dx++) {
                    int x = cell[k][0] + dx, y = cell[k][1] + dy, z = cell[k][2] + dz;
                    if (dx * dx + dy * dy + dz * dz > r * r || x < 0 || x >= h->n[0] || y < 0 || y >= h->n[1] ||
                        z < 0 || z >= h->n[2])
                        continue;
                    int q = at[ws_hull_index(h, x, y, z)];
                    if (q < 0) continue;
                    double d[3] = {dx, dy, dz};
                    for (int a = 0; a < 3; a++) sum[a] += d[a];
                    sq[0] += d[0] * d[0], sq[1] += d[1] * d[1], sq[2] += d[2] * d[2];
                    sq[3] += d[0] * d[1], sq[4] += d[0] * d[2], sq[5] += d[1] * d[2];
                    m++;
                }
        e->crease[k] = (uint8_t)(m >= 3 && surface_variation(sum, sq, m) > limit);
    }
    free(cell);
    free(at);
    return WS_OK;
}

void ws_line_evidence_free(ws_line_evidence *e) {
    free(e->crease);
    e->crease = NULL;
}

/* Z and K of a view (line_evidence.h) into z and crease (H x W; nearest:
 * scratch, the surface voxel nearest at each pixel; far, unless NULL: the
 * farthest surface voxel's depth). */
static void hull_depth(const ws_line_evidence *e, const ws_camera *cam, float *z, int *nearest, uint8_t *crease,
                       float *far) {
    const ws_scene_hull *hl = e->hull;
    ws_hull_surface_depth(&hl->surface, cam, hl->hull.voxel * sqrt(3.0) / 2, z, nearest, far);
    for (size_t p = 0; p < (size_t)cam->width * cam->height; p++)
        crease[p] = nearest[p] < 0 ? 0 : e->crease[nearest[p]];
}

/* Whether pixel (i, j) of z lies nearer than a 4-neighbour by more than
 * WS_EVIDENCE_DEPTH_JUMP of its depth: the near side of a hull contour. */
static int depth_jump(const float *z, int W, int H, int i, int j) {
    static const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
    float here = z[(size_t)i * W + j];
    if (!isfinite(here)) return 0;
    for (int k = 0; k < 4; k++) {
        int ii = i + di[k], jj = j + dj[k];
        if (ii < 0 || ii >= H || jj < 0 || jj >= W) continue;
        float q = z[(size_t)ii * W + jj];
        if (isfinite(q) && q - here > WS_EVIDENCE_DEPTH_JUMP * here) return 1;
    }
    return 0;
}

/* Buffers of one view, H x W each. */
typedef struct {
    float *z, *dist, *inside, *far;
    int *nearest;
    uint8_t *crease, *set, *support, *covered;
} view_buffers;

static int buffers_alloc(view_buffers *b, size_t n, ws_status *st) {
    memset(b, 0, sizeof *b);
    b->z = ws_malloc(n * sizeof(float), "hull lines", st);
    b->dist = b->z ? ws_malloc(n * sizeof(float), "hull lines", st) : NULL;
    b->inside = b->dist ? ws_malloc(n * sizeof(float), "hull lines", st) : NULL;
    b->far = b->inside ? ws_malloc(n * sizeof(float), "hull lines", st) : NULL;
    b->crease = b->far ? ws_malloc(n, "hull lines", st) : NULL;
    b->set = b->crease ? ws_malloc(n, "hull lines", st) : NULL;
    b->support = b->set ? ws_malloc(n, "hull lines", st) : NULL;
    b->covered = b->support ? ws_malloc(n, "hull lines", st) : NULL;
    b->nearest = b->covered ? ws_malloc(n * sizeof(int), "hull lines", st) : NULL;
    return b->nearest ? WS_OK : st->code;
}

static void buffers_free(view_buffers *b) {
    free(b->z);
    free(b->dist);
    free(b->inside);
    free(b->far);
    free(b->crease);
    free(b->set);
    free(b->support);
    free(b->covered);
    free(b->nearest);
}

/* support from z and crease, grown by reach pixels (b->dist is
 * overwritten). */
static int support_map(view_buffers *b, int W, int H, double reach, uint8_t *support, ws_status *st) {
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            size_t p = (size_t)i * W + j;
            b->set[p] = (uint8_t)(isfinite(b->z[p]) && (b->crease[p] || depth_jump(b->z, W, H, i, j)));
        }
    if (ws_distance_map(b->set, W, H, b->dist, st)) return st->code;
    for (size_t p = 0; p < (size_t)W * H; p++) support[p] = b->dist[p] <= reach;
    return WS_OK;
}

int ws_line_evidence_view(const ws_line_evidence *e, const ws_camera *cam, uint8_t *support, ws_status *st) {
    view_buffers b;
    int rc = buffers_alloc(&b, (size_t)cam->width * cam->height, st);
    if (!rc) {
        hull_depth(e, cam, b.z, b.nearest, b.crease, NULL);
        rc = support_map(&b, cam->width, cam->height, WS_EVIDENCE_REACH_PX, support, st);
    }
    buffers_free(&b);
    return rc;
}

/* The drawing's two layers apart (H x W each): lines = 1 on the outline
 * and contour pixels, keep = 1 where the curves are drawn. */
static int evidence_layers(const ws_line_evidence *e, const ws_hull_outline *outline, const ws_camera *cam,
                           uint8_t *lines, uint8_t *keep, ws_status *st) {
    const int W = cam->width, H = cam->height;
    const size_t n = (size_t)W * H;
    const double thin = WS_DRAWING_THIN_PX, margin = WS_DRAWING_CURVE_MARGIN_PX;
    view_buffers b;
    int rc = buffers_alloc(&b, n, st);
    if (!rc) {
        hull_depth(e, cam, b.z, b.nearest, b.crease, b.far);
        rc = support_map(&b, W, H, WS_DRAWING_SUPPORT_PX, b.support, st);
    }
    /* inside: the distance to the voxel hull's outside; the exact test
     * only where that is within the band */
    if (!rc) {
        for (size_t p = 0; p < n; p++) b.set[p] = !isfinite(b.z[p]);
        rc = ws_distance_map(b.set, W, H, b.inside, st);
    }
    if (!rc) {
        /* the depths between which a ray can meet the exact hull, inside the
         * voxel hull: its nearest and farthest surface voxels' centres, a
         * voxel's ball (and the discs' rounding) either side; dist holds
         * the near ones until it is remade below */
        const double widen = 2 * e->hull->hull.voxel;
        for (size_t p = 0; p < n; p++) {
            b.covered[p] = !b.set[p];
            b.set[p] = !b.set[p] && b.inside[p] <= WS_DRAWING_BAND_PX;
            b.dist[p] = (float)(b.z[p] - widen);
            b.far[p] = (float)(b.far[p] + widen);
        }
        rc = ws_hull_outline_cover(outline, cam, b.set, b.dist, b.far, b.covered, st);
    }
    /* inside: now the distance to the pixels the exact hull does not cover */
    if (!rc) {
        for (size_t p = 0; p < n; p++) b.set[p] = !b.covered[p];
        rc = ws_distance_map(b.set, W, H, b.inside, st);
    }
    /* dist: to where the covered region is wider than a thin part */
    if (!rc) {
        for (size_t p = 0; p < n; p++) b.set[p] = b.inside[p] > thin;
        rc = ws_distance_map(b.set, W, H, b.dist, st);
    }
    if (!rc)
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++) {
                size_t p = (size_t)i * W + j;
                int in = b.covered[p], wide = b.dist[p] <= thin + 1.5, outline_px = 0;
                for (int k = 0; k < 4 && in && wide && !outline_px; k++) {
                    int ii = i + (k == 0) - (k == 1), jj = j + (k == 2) - (k == 3);
                    outline_px = ii >= 0 && ii < H && jj >= 0 && jj < W && !b.covered[(size_t)ii * W + jj];
                }
                lines[p] = (uint8_t)(outline_px || (in && wide && depth_jump(b.z, W, H, i, j)));
                keep[p] = (uint8_t)(b.support[p] && b.inside[p] > margin);
                b.set[p] = (uint8_t)(in && !wide);
            }
    /* the thin parts, which only the curves draw, and their edge */
    if (!rc) rc = ws_distance_map(b.set, W, H, b.dist, st);
    for (size_t p = 0; !rc && p < n; p++) keep[p] |= b.dist[p] <= WS_DRAWING_THIN_EDGE_PX;
    buffers_free(&b);
    return rc;
}

/* The drawing a user gets of a view (what the test renders, the report,
 * the SVG and the drawing score show): the view-dependent lines of the
 * hull beside the view-independent curves, as 3Doodle draws its proxies'
 * contours. A 3D curve on a smooth object is an outline in some views and
 * crosses the body in the others; the hull's own outline is the outline in
 * every view. With curves the sketch's render (io/turntable.h: grey,
 * strokes dark):
 *   covered = the pixels the voxel hull's surface covers, except within
 *             WS_DRAWING_BAND_PX of its edge, where each pixel is tested
 *             exactly (geometry/hull_outline.h): the voxel hull stands a
 *             pixel or two proud of the object, the exact one does not;
 *   inside  = the distance to the pixels not covered;
 *   margin = WS_DRAWING_CURVE_MARGIN_PX, thin = WS_DRAWING_THIN_PX;
 *   outline = covered pixels with a 4-neighbour not covered, and contour =
 *             the near sides of the voxel hull's depth jumps on covered
 *             pixels, both only within thin + 1.5 px of where inside >
 *             thin (a thin part, a wire, is drawn by its curve, not by two
 *             outlines);
 *   drawing = 0 on outline and contour pixels; elsewhere the curves' grey
 *             where the hull supports a line (as ws_line_evidence_view,
 *             grown by WS_DRAWING_SUPPORT_PX instead) and
 *             inside > margin (curves along the outline are left to it),
 *             and within WS_DRAWING_THIN_EDGE_PX of a thin part's covered
 *             pixels (no outline is drawn there), else 255.
 * The margin and hull resolution were chosen on the duck's and the rose's
 * test views (docs/RESULTS.md, "Drawings of smooth objects").
 * drawing: H x W, and may be curves itself. */
static int draw_view(const ws_line_evidence *e, const ws_hull_outline *outline, const ws_camera *cam,
                   const unsigned char *curves, unsigned char *drawing, ws_status *st) {
    const size_t n = (size_t)cam->width * cam->height;
    uint8_t *lines = ws_malloc(2 * n, "hull lines", st);
    if (!lines) return st->code;
    int rc = evidence_layers(e, outline, cam, lines, lines + n, st);
    for (size_t p = 0; !rc && p < n; p++) drawing[p] = lines[p] ? 0 : lines[n + p] ? curves[p] : 255;
    free(lines);
    return rc;
}

int ws_drawing_hull_make(ws_drawing_hull *d, const ws_scene *scene, ws_status *st) {
    memset(d, 0, sizeof *d);
    const ws_split *train = &scene->split[WS_TRAIN];
    d->nviews = train->n;
    d->sil = ws_calloc(train->n ? (size_t)train->n : 1, sizeof *d->sil, "silhouettes", st);
    d->views = d->sil ? ws_malloc((train->n ? (size_t)train->n : 1) * sizeof *d->views, "silhouettes", st) : NULL;
    int rc = d->views ? WS_OK : st->code;
    for (int v = 0; v < train->n && !rc; v++) {
        rc = ws_view_silhouette(&train->views[v], &d->sil[v], st);
        d->views[v] = (ws_hull_view){.cam = &train->views[v].cam, .sil = &d->sil[v]};
    }
    /* Over a busy background without masks a silhouette is most of the
     * frame; a hull carved from those is the whole box, whose outline is
     * no line of the object and which hides every curve inside it. */
    int empty, edge;
    if (!rc && !ws_check_silhouettes_usable(d->sil, train->n, &empty, &edge))
        rc = ws_fail(st, WS_EINPUT, "%s: %d of the %d train views have no usable silhouette (%d find no object, %d "
                     "hold half the frame's edge or more), so no hull outlines the object", scene->dir,
                     empty + edge, train->n, empty, edge);
    if (!rc) rc = ws_scene_hull_make(scene, WS_TRAIN, d->sil, WS_DRAWING_HULL_RESOLUTION, &d->hull, st);
    if (!rc) rc = ws_line_evidence_init(&d->evidence, &d->hull, st);
    double lo[3], hi[3];
    if (!rc) ws_hull_outline_box(&d->hull.hull, lo, hi);
    if (!rc) rc = ws_hull_outline_init(&d->outline, d->views, train->n, d->hull.hull.tolerance, lo, hi, st);
    if (rc) ws_drawing_hull_free(d);
    return rc;
}

void ws_drawing_hull_free(ws_drawing_hull *d) {
    ws_hull_outline_free(&d->outline);
    ws_line_evidence_free(&d->evidence);
    ws_scene_hull_free(&d->hull);
    for (int v = 0; d->sil && v < d->nviews; v++) ws_silhouette_free(&d->sil[v]);
    free(d->sil);
    free(d->views);
    d->sil = NULL;
    d->views = NULL;
}

int ws_drawing_hull_layers(const ws_drawing_hull *d, const ws_camera *cam, uint8_t *lines, uint8_t *keep,
                           ws_status *st) {
    return evidence_layers(&d->evidence, &d->outline, cam, lines, keep, st);
}

int ws_drawing_hull_render(void *ctx, const ws_camera *cam, const unsigned char *curves, unsigned char *drawing,
                           ws_status *st) {
    const ws_drawing_hull *d = ctx;
    return draw_view(&d->evidence, &d->outline, cam, curves, drawing, st);
}
