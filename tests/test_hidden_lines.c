/* test_hidden_lines.c: hidden-line removal by the visual hull
 * (objective/hidden_lines.h). On a synthetic cube, in every training view:
 * the vertex nearest the camera, the centre of the face turned most towards
 * it, and the vertex farthest left in the image (on the contour) are
 * visible; the centre is hidden in every view and the farthest vertex,
 * behind the solid, in most (near a contour the window lets it through); a
 * point where no hull projects is visible however far; where a face is seen
 * within 30 degrees of head-on, the point 1.25 x WS_HIDDEN_TOLERANCE_HEAD_ON
 * voxels behind its centre along the ray is hidden (the tolerance there is
 * at most 1.16 x the head-on one; with the grazing WS_HIDDEN_TOLERANCE
 * everywhere it was drawn in 4 of the 6 such views). On a trefoil tube, the axis point
 * nearest the camera (a tube radius behind the hull's surface) is visible
 * in every view. Visible means drawn: a Gaussian at the point splatted with
 * the view's far limit (render/splat.h) leaves ink; the tolerance is added
 * in the far map, so no test here repeats it. */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_util.h"
#include "metrics/metrics.h"
#include "objective/hidden_lines.h"
#include "render/splat.h"
#include "synth/synth.h"
#include "scene_load.h"

#define SIZE 128

static double depth_of(const ws_camera *cam, const double p[3], double *u, double *v) {
    double c[3];
    ws_camera_to_cam(cam, p, c);
    return ws_camera_project(cam, c, u, v);
}

/* Does a Gaussian of radius 0.01 at p draw in training view `view` with
 * hidden lines removed by hl? */
static int visible(ws_hidden_lines *hl, const ws_scene *scene, int view, const double p[3]) {
    static double alpha[SIZE * SIZE];
    ws_status st;
    ws_splat *s = NULL;
    ws_splat_options so;
    ws_splat_options_default(&so);
    int rc = ws_hidden_lines_far(hl, WS_TRAIN, view, &so.far, &st) || ws_splat_create(&s, SIZE, SIZE, &st) ||
             ws_splat_forward(s, &scene->split[WS_TRAIN].views[view].cam, p, 1, 0.01, &so, alpha, &st);
    ws_splat_free(s);
    if (rc) {
        CHECK(0, "visible: %s", st.msg);
        return -1;
    }
    double ink = 0;
    for (int k = 0; k < SIZE * SIZE; k++) ink += alpha[k];
    return ink > 0;
}

static int make_scene(const char *name, const char *dir, ws_scene *scene, ws_curves *gt) {
    ws_status st;
    ws_synth_options syn;
    synth_options_at(&syn, SIZE, 24, 0, 0);
    char path[700];
    snprintf(path, sizeof path, "%s/gt_curves.json", dir);
    int rc = ws_synth_write(name, dir, &syn, &st);
    if (!rc) rc = load_scene_at(scene, dir, SIZE, &st);
    if (!rc) rc = ws_curves_load(path, gt, &st);
    CHECK(rc == WS_OK, "%s: %s", name, st.msg);
    return rc;
}

static void cube(const char *tmp) {
    char dir[600];
    snprintf(dir, sizeof dir, "%s/cube", tmp);
    ws_scene scene = {0};
    ws_curves gt = {0};
    ws_hidden_lines *hl = NULL;
    ws_view_targets *targets = NULL;
    ws_scene_hull hull = {0};
    const ws_silhouette *sil;
    ws_status st;
    if (make_scene("cube", dir, &scene, &gt) || ws_view_targets_create(&targets, &scene, &st) ||
        ws_view_targets_silhouettes(targets, WS_TRAIN, &sil, &st) ||
        ws_scene_hull_make(&scene, WS_TRAIN, sil, WS_HULL_INIT_RESOLUTION, &hull, &st) ||
        ws_hidden_lines_create(&hl, &scene, &hull, targets, &st)) {
        CHECK(!hl, "hidden lines: %s", st.msg);
        goto done;
    }
    /* the vertices: every curve's end points (each twice or more); the
     * centre, half a side behind any face */
    double lo[3], hi[3], center[3];
    ws_curves_bbox(&gt, lo, hi);
    for (int x = 0; x < 3; x++) center[x] = 0.5 * (lo[x] + hi[x]);
    const ws_split *train = &scene.split[WS_TRAIN];
    int hidden_far = 0, bad_near = 0, bad_face = 0, bad_contour = 0, bad_empty = 0, bad_center = 0;
    int head_on = 0, bad_behind = 0;
    for (int k = 0; k < train->n; k++) {
        const ws_camera *cam = &train->views[k].cam;
        int near = 0, far = 0, left = 0;
        double dn = INFINITY, df = -INFINITY, ul = INFINITY;
        for (int e = 0; e < 2 * gt.n; e++) {
            const double *p = gt.P + (e / 2) * WS_CURVE_FLOATS + (e % 2) * 9;
            double u, v, d = depth_of(cam, p, &u, &v);
            if (d < dn) dn = d, near = e;
            if (d > df) df = d, far = e;
            if (u < ul) ul = u, left = e;
        }
#define VERTEX(e) (gt.P + ((e) / 2) * WS_CURVE_FLOATS + ((e) % 2) * 9)
        bad_near += visible(hl, &scene, k, VERTEX(near)) != 1;
        hidden_far += visible(hl, &scene, k, VERTEX(far)) == 0;
        bad_contour += visible(hl, &scene, k, VERTEX(left)) != 1;
        bad_center += visible(hl, &scene, k, center) != 0;
        /* of the faces at the nearest vertex n, whose centres lie half way
         * between two of its neighbours, the one whose centre is nearest */
        const double *n = VERTEX(near), *nb[3];
        int found = 0;
        for (int e = 0; e < 2 * gt.n && found < 3; e++)
            if (!memcmp(VERTEX(e), n, 3 * sizeof(double))) nb[found++] = VERTEX(e ^ 1);
        double face[3] = {0}, best = INFINITY;
        for (int a = 0; a < found; a++)
            for (int b = a + 1; b < found; b++) {
                double f[3], u, v;
                for (int x = 0; x < 3; x++) f[x] = 0.5 * (nb[a][x] + nb[b][x]);
                double d = depth_of(cam, f, &u, &v);
                if (d < best) best = d, memcpy(face, f, sizeof f);
            }
        CHECK(found == 3, "cube: the nearest vertex has %d edges", found);
        bad_face += visible(hl, &scene, k, face) != 1;
        /* that face's normal (from the cube's centre) against the ray */
        double ray[3], normal[3], rr = 0, nn = 0, dot = 0;
        for (int x = 0; x < 3; x++) {
            ray[x] = face[x] - cam->c2w[x][3];
            normal[x] = face[x] - center[x];
            rr += ray[x] * ray[x], nn += normal[x] * normal[x], dot += ray[x] * normal[x];
        }
        if (-dot >= cos(M_PI / 6) * sqrt(rr * nn)) {
            double behind[3], t = 1.25 * WS_HIDDEN_TOLERANCE_HEAD_ON * hull.hull.voxel / sqrt(rr);
            for (int x = 0; x < 3; x++) behind[x] = face[x] + t * ray[x];
            head_on++;
            bad_behind += visible(hl, &scene, k, behind) != 0;
        }
        /* far along the ray through the image's corner pixel: no hull there */
        double dir[3], c[3], p[3];
        ws_camera_ray(cam, 0.5, 0.5, dir);
        for (int x = 0; x < 3; x++) c[x] = 100 * dir[x];
        for (int x = 0; x < 3; x++)
            p[x] = cam->c2w[x][0] * c[0] + cam->c2w[x][1] * c[1] + cam->c2w[x][2] * c[2] + cam->c2w[x][3];
        bad_empty += visible(hl, &scene, k, p) != 1;
    }
#undef VERTEX
    CHECK(!bad_near && !bad_face && !bad_contour && !bad_empty,
          "cube: hidden in views where visible: nearest vertex %d, front face %d, contour vertex %d, no hull %d",
          bad_near, bad_face, bad_contour, bad_empty);
    CHECK(hidden_far >= train->n * 3 / 4, "cube: the farthest vertex is hidden in %d of %d views", hidden_far,
          train->n);
    CHECK(!bad_center, "cube: the centre is drawn in %d of %d views", bad_center, train->n);
    CHECK(head_on > 0 && !bad_behind, "cube: behind a face seen head-on, drawn in %d of %d views", bad_behind,
          head_on);
    printf("cube: the farthest vertex hidden in %d of %d views; a face seen head-on in %d\n", hidden_far, train->n,
           head_on);
done:
    ws_hidden_lines_free(hl);
    ws_scene_hull_free(&hull);
    ws_view_targets_free(targets);
    ws_scene_free(&scene);
    ws_curves_free(&gt);
}

static void trefoil(const char *tmp) {
    char dir[600];
    snprintf(dir, sizeof dir, "%s/trefoil", tmp);
    ws_scene scene = {0};
    ws_curves gt = {0};
    ws_hidden_lines *hl = NULL;
    ws_view_targets *targets = NULL;
    ws_status st;
    if (make_scene("trefoil", dir, &scene, &gt) || ws_view_targets_create(&targets, &scene, &st) ||
        ws_hidden_lines_create(&hl, &scene, NULL, targets, &st)) {
        CHECK(!hl, "hidden lines: %s", st.msg);
        goto done;
    }
    const ws_split *train = &scene.split[WS_TRAIN];
    int bad = 0;
    for (int k = 0; k < train->n; k++) {
        double best = INFINITY, nearest[3] = {0};
        for (int ci = 0; ci < gt.n; ci++)
            for (int j = 0; j <= 50; j++) {
                double p[3], u, v;
                ws_curve_point(&gt, ci, j / 50.0, p);
                double d = depth_of(&train->views[k].cam, p, &u, &v);
                if (d < best) best = d, memcpy(nearest, p, sizeof p);
            }
        bad += visible(hl, &scene, k, nearest) != 1;
    }
    CHECK(bad == 0, "trefoil: the nearest point of the tube's axis is hidden in %d of %d views", bad, train->n);
done:
    ws_hidden_lines_free(hl);
    ws_view_targets_free(targets);
    ws_scene_free(&scene);
    ws_curves_free(&gt);
}

int main(void) {
    const char *tmp = test_tmpdir("hidden");
    cube(tmp);
    trefoil(tmp);
    return check_summary();
}
