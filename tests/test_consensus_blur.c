/* slow test */
/* test_consensus_blur.c: the edges the views agree on (objective/
 * edge_consensus.h) when the photos are a little soft, as every real
 * camera's are (a lens, JPEG, a photo resampled to the working view). The
 * bracket in the box room as the capture bed has it (`scene bracket
 * --background room --layout nerfstudio --size 288x224`: no mask, 48 train
 * views, the region from the sparse points), its train photos blurred by a
 * Gaussian of sigma WS_TEST_BLUR px (about what a lens' undistortion
 * does); along each of its 18 edges, the share of points with a kept point
 * within two grid cubes:
 *   - at least MIN_COVER of every edge on the faces of the object's box.
 *     A lower edge, seen by a third of the views and most of them on an
 *     edge, votes weak along its length with a gap here and there once the
 *     photos are soft, and a gap one cube wide must not cut it from the
 *     strong points it grows from (WS_CONSENSUS_WEAK_REACH: a reach of 1
 *     keeps a quarter of the lower front edge);
 *   - the concave crease, off those faces, is only printed: the photo
 *     hull hides it from most views, sharp or soft (docs/RESULTS.md,
 *     "Soft photos"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "geometry/roi.h"
#include "metrics/metrics.h"
#include "objective/edge_consensus.h"
#include "render/curves.h"
#include "render/pyramid.h"
#include "scene_load.h"
#include "synth/synth.h"
#include "test_util.h"

enum { SIZE = 224, FRAME_W = 288, TRAIN = 48, SAMPLES = 40 };
#define WS_TEST_BLUR 0.5
#define MIN_COVER 0.7

/* Each plane of img blurred by a Gaussian of sigma px, borders repeated
 * (a camera's softness, not a dark frame). */
static void soften(ws_image *img, double sigma) {
    const size_t hw = (size_t)img->width * img->height;
    ws_blur_kernel g;
    ws_blur_kernel_init(&g, sigma);
    double *plane = malloc(3 * hw * sizeof *plane), *blurred = plane + hw, *tmp = plane + 2 * hw;
    for (int c = 0; c < img->channels && plane; c++) {
        float *p = img->data + c * hw;
        for (size_t q = 0; q < hw; q++) plane[q] = p[q];
        ws_blur_repeat_forward(&g, plane, blurred, tmp, img->width, img->height);
        for (size_t q = 0; q < hw; q++) p[q] = (float)blurred[q];
    }
    free(plane);
}

/* cover[e]: the share of SAMPLES points along edge e of gt with a kept
 * point of c within two grid cubes. */
static void edge_cover(const ws_edge_consensus *c, const ws_curves *gt, double *cover) {
    const double reach = 2 * c->voxel;
    for (int e = 0; e < gt->n; e++) {
        int near = 0;
        for (int s = 0; s < SAMPLES; s++) {
            double p[3];
            ws_curve_point(gt, e, (s + 0.5) / SAMPLES, p);
            for (int k = 0; k < c->n; k++) {
                const double *q = c->p + 3 * k;
                if ((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]) <=
                    reach * reach) {
                    near++;
                    break;
                }
            }
        }
        cover[e] = (double)near / SAMPLES;
    }
}

int main(void) {
    const char *tmp = test_tmpdir("consensus_blur");
    char dir[300], path[400];
    ws_status st;
    ws_synth_options syn;
    synth_options_at(&syn, SIZE, TRAIN, 0, 0);
    syn.room = 1;
    syn.nerfstudio = 1; /* its sparse points place the region, as in a capture */
    syn.width = FRAME_W;
    syn.height = SIZE;
    snprintf(dir, sizeof dir, "%s/bracket", tmp);
    snprintf(path, sizeof path, "%s/gt_curves.json", dir);
    ws_scene scene = {0};
    ws_curves gt = {0};
    ws_roi roi;
    ws_status roi_st;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = SIZE;
    int rc = ws_synth_write("bracket", dir, &syn, &st);
    if (!rc) rc = ws_roi_load_scene(&scene, dir, &so, NULL, &roi, &roi_st, &st);
    if (!rc) rc = ws_curves_load(path, &gt, &st);
    CHECK(rc == WS_OK && !roi_st.code && gt.n == 18, "setup: %s %s (%d edges)", st.msg, roi_st.msg, gt.n);
    if (rc) return check_summary();

    double cover[18];
    for (int v = 0; v < scene.split[WS_TRAIN].n; v++) soften(&scene.split[WS_TRAIN].views[v].photo, WS_TEST_BLUR);
    ws_edge_consensus c = {0};
    rc = ws_edge_consensus_make(&scene, &roi, WS_CONSENSUS_RESOLUTION, &c, &st);
    CHECK(rc == WS_OK, "consensus: %s", st.msg);
    if (!rc) edge_cover(&c, &gt, cover);
    printf("blurred photos, %d kept points; each edge's cover:", c.n);
    for (int e = 0; e < gt.n && !rc; e++) printf(" %.2f", cover[e]);
    printf("\n");
    ws_edge_consensus_free(&c);
    /* the crease: the one edge off the faces of the object's box */
    double lo[3], hi[3];
    ws_curves_bbox(&gt, lo, hi);
    for (int e = 0; e < gt.n && !rc; e++) {
        double mid[3];
        ws_curve_point(&gt, e, 0.5, mid);
        int on_face = 0;
        for (int a = 0; a < 3; a++) on_face |= fabs(mid[a] - lo[a]) < 1e-9 || fabs(mid[a] - hi[a]) < 1e-9;
        if (!on_face) {
            printf("edge %d, the concave crease: %.2f covered\n", e, cover[e]);
            continue;
        }
        CHECK(cover[e] >= MIN_COVER, "edge %d: only %.2f of it covered", e, cover[e]);
    }
    ws_curves_free(&gt);
    ws_scene_free(&scene);
    return check_summary();
}
