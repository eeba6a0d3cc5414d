/* test_hull_outline.c: the exact visual hull's cover of a view
 * (geometry/hull_outline.h) against known geometry: a unit sphere seen by
 * 200 cameras spread over a sphere of radius 4, each silhouette the
 * pixels whose centre ray meets it (a mask, so its edge lies on the pixel
 * edges). A new camera, between the others and nearer, must see the
 * analytic circle the sphere projects to: every pixel whose centre lies
 * more than 0.5 px from it covered exactly when inside it. One silhouette
 * emptied (a bad mask) carves everything at tolerance 0 and nothing at
 * tolerance 1. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "geometry/hull_outline.h"

#define NVIEWS 200
#define TRAIN_SIZE 128
#define TEST_SIZE 96
#define ANGLE 0.6 /* camera_angle_x, radians */

/* A camera at p looking at the origin, +z up in its image. */
static void look_at(ws_camera *cam, const double p[3], int size, ws_status *st) {
    double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    double z[3] = {p[0] / len, p[1] / len, p[2] / len}, up[3] = {0, 0, 1};
    if (fabs(z[2]) > 0.99) up[0] = 1, up[2] = 0;
    double x[3] = {up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]};
    double xl = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int a = 0; a < 3; a++) x[a] /= xl;
    double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    double c2w[4][4] = {{x[0], y[0], z[0], p[0]}, {x[1], y[1], z[1], p[1]}, {x[2], y[2], z[2], p[2]}, {0, 0, 0, 1}};
    CHECK(ws_camera_init(cam, c2w, ANGLE, size, size, "test camera", st) == 0, "%s", st->msg);
}

/* Whether the ray through pixel (i, j)'s centre meets the unit sphere. */
static int ray_hits(const ws_camera *cam, int i, int j) {
    double D[3], w[3], o[3];
    ws_camera_pixel_ray(cam, i, j, D);
    for (int x = 0; x < 3; x++) w[x] = cam->R[0][x] * D[0] + cam->R[1][x] * D[1] + cam->R[2][x] * D[2];
    ws_camera_position(cam, o);
    double a = w[0] * w[0] + w[1] * w[1] + w[2] * w[2], b = o[0] * w[0] + o[1] * w[1] + o[2] * w[2];
    double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - 1;
    return b * b - a * c >= 0;
}

int main(void) {
    ws_status st;
    ws_status_clear(&st);
    static ws_camera cams[NVIEWS];
    static ws_silhouette sil[NVIEWS];
    static ws_hull_view views[NVIEWS];
    ws_image photo, mask;
    CHECK(ws_image_alloc(&photo, TRAIN_SIZE, TRAIN_SIZE, 3, &st) == 0 &&
              ws_image_alloc(&mask, TRAIN_SIZE, TRAIN_SIZE, 1, &st) == 0,
          "%s", st.msg);
    memset(photo.data, 0, sizeof(float) * 3 * TRAIN_SIZE * TRAIN_SIZE);
    for (int k = 0; k < NVIEWS; k++) {
        /* a Fibonacci sphere */
        double zz = 1 - (k + 0.5) * 2.0 / NVIEWS, r = sqrt(1 - zz * zz), phi = k * M_PI * (3 - sqrt(5.0));
        double p[3] = {4 * r * cos(phi), 4 * r * sin(phi), 4 * zz};
        look_at(&cams[k], p, TRAIN_SIZE, &st);
        for (int i = 0; i < TRAIN_SIZE; i++)
            for (int j = 0; j < TRAIN_SIZE; j++) mask.data[i * TRAIN_SIZE + j] = (float)ray_hits(&cams[k], i, j);
        CHECK(ws_silhouette_make(&photo, &mask, &sil[k], &st) == 0, "%s", st.msg);
        views[k] = (ws_hull_view){.cam = &cams[k], .sil = &sil[k]};
    }
    ws_camera test;
    const double at[3] = {3.5 * 0.48, 3.5 * -0.6, 3.5 * 0.64};
    look_at(&test, at, TEST_SIZE, &st);
    const double lo[3] = {-2, -2, -2}, hi[3] = {2, 2, 2};
    ws_hull_outline o;
    CHECK(ws_hull_outline_init(&o, views, NVIEWS, 0, lo, hi, &st) == 0, "%s", st.msg);
    static uint8_t band[TEST_SIZE * TEST_SIZE], covered[TEST_SIZE * TEST_SIZE];
    memset(band, 1, sizeof band);
    memset(covered, 7, sizeof covered);
    CHECK(ws_hull_outline_cover(&o, &test, band, NULL, NULL, covered, &st) == 0, "%s", st.msg);
    /* the circle: the test camera looks at the sphere's centre from 3.5 */
    double d = sqrt(at[0] * at[0] + at[1] * at[1] + at[2] * at[2]), radius = test.focal / sqrt(d * d - 1);
    int wrong = 0, checked = 0, ring = 0;
    double worst = 0;
    for (int i = 0; i < TEST_SIZE; i++)
        for (int j = 0; j < TEST_SIZE; j++) {
            double off = hypot(j + 0.5 - test.cx, i + 0.5 - test.cy) - radius;
            int want = off < 0, got = covered[i * TEST_SIZE + j];
            if (got != want) worst = fmax(worst, fabs(off));
            if (fabs(off) <= 0.5) {
                ring++;
                continue;
            }
            checked++;
            wrong += got != want;
        }
    CHECK(checked > 8000 && ring > 100, "%d pixels checked, %d on the ring", checked, ring);
    CHECK(wrong == 0, "%d of %d pixels wrong, the worst %.3f px from the circle (radius %.2f px)", wrong, checked,
          worst, radius);
    /* part of a band: the pixels outside it keep their value */
    memset(band, 0, sizeof band);
    band[(TEST_SIZE / 2) * TEST_SIZE + TEST_SIZE / 2] = 1;
    memset(covered, 7, sizeof covered);
    CHECK(ws_hull_outline_cover(&o, &test, band, NULL, NULL, covered, &st) == 0, "%s", st.msg);
    CHECK(covered[(TEST_SIZE / 2) * TEST_SIZE + TEST_SIZE / 2] == 1 && covered[0] == 7, "band: centre %d, corner %d",
          covered[(TEST_SIZE / 2) * TEST_SIZE + TEST_SIZE / 2], covered[0]);
    ws_hull_outline_free(&o);
    /* a bad mask: view 0 sees nothing */
    memset(sil[0].in, 0, TRAIN_SIZE * TRAIN_SIZE);
    for (int p = 0; p < TRAIN_SIZE * TRAIN_SIZE; p++) sil[0].distance[p] = INFINITY;
    memset(band, 1, sizeof band);
    for (int tolerance = 0; tolerance <= 1; tolerance++) {
        CHECK(ws_hull_outline_init(&o, views, NVIEWS, tolerance, lo, hi, &st) == 0, "%s", st.msg);
        CHECK(ws_hull_outline_cover(&o, &test, band, NULL, NULL, covered, &st) == 0, "%s", st.msg);
        int count = 0, want = 0;
        for (int i = 0; i < TEST_SIZE; i++)
            for (int j = 0; j < TEST_SIZE; j++) {
                count += covered[i * TEST_SIZE + j];
                want += hypot(j + 0.5 - test.cx, i + 0.5 - test.cy) < radius;
            }
        if (tolerance == 0) CHECK(count == 0, "an empty silhouette at tolerance 0: %d pixels covered", count);
        else CHECK(abs(count - want) < ring, "tolerance 1: %d pixels covered, %d inside the circle", count, want);
        ws_hull_outline_free(&o);
    }
    CHECK(ws_hull_outline_init(&o, views, NVIEWS, 251, lo, hi, &st) == WS_EINTERNAL, "tolerance 251 accepted");
    for (int k = 0; k < NVIEWS; k++) ws_silhouette_free(&sil[k]);
    ws_image_free(&photo);
    ws_image_free(&mask);
    return check_summary();
}
