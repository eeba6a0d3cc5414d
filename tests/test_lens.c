/* test_lens.c: lens models (render/lens.h).
 * - the inverse against an independent reference: tests/fixtures/lens_points.txt
 *   (tools/lens_reference.py, OpenCV's published formulas in plain python)
 *   holds pinhole pixels and their distorted pixels for every distorting
 *   COLMAP model; lens.c's inverse takes each distorted pixel back within
 *   0.01 px, and its forward model agrees with the reference to 1e-6 px;
 * - forward(inverse(p)) = p to 1e-9 px over a whole frame, and every
 *   point of a frame's border has an inverse;
 * - lenses that fold the image, unknown models, wrong parameter counts:
 *   their exact one-line messages. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "check.h"
#include "io/undistort.h"
#include "render/lens.h"

#define FIXTURE "tests/fixtures/lens_points.txt"

static void reference_points(void) {
    FILE *f = fopen(FIXTURE, "r");
    CHECK(f != NULL, "%s: cannot open", FIXTURE);
    if (!f) return;
    char model[64];
    int w, h, np, lines = 0;
    double worst_inverse = 0, worst_forward = 0;
    while (fscanf(f, "%63s %d %d %d", model, &w, &h, &np) == 4) {
        double q[12], u, v, ud, vd;
        for (int i = 0; i < np && i < 12; i++) CHECK(fscanf(f, "%lf", &q[i]) == 1, "param");
        CHECK(fscanf(f, "%lf %lf %lf %lf", &u, &v, &ud, &vd) == 4, "point");
        ws_lens lens;
        ws_status st = {0};
        CHECK(ws_lens_from_colmap(&lens, model, q, np, w, h, "ref", &st) == WS_OK, "%s", st.msg);
        double x, y, xd, yd;
        int rc = ws_lens_undistort(&lens, (ud - lens.cx) / lens.fx, (vd - lens.cy) / lens.fy, &x, &y);
        CHECK(rc == 0, "%s: no inverse at %g %g", model, ud, vd);
        worst_inverse = fmax(worst_inverse, hypot(x * lens.fx + lens.cx - u, y * lens.fy + lens.cy - v));
        ws_lens_distort(&lens, (u - lens.cx) / lens.fx, (v - lens.cy) / lens.fy, &xd, &yd);
        worst_forward = fmax(worst_forward, hypot(xd * lens.fx + lens.cx - ud, yd * lens.fy + lens.cy - vd));
        lines++;
    }
    fclose(f);
    CHECK(lines > 250, "%d reference points", lines);
    CHECK(worst_inverse < 0.01, "inverse off the reference by %g px", worst_inverse);
    CHECK(worst_forward < 1e-6, "forward off the reference by %g px", worst_forward);
    printf("reference: %d points, inverse within %.2e px, forward within %.2e px\n", lines,
           worst_inverse, worst_forward);
}

/* Every pixel centre of a 160 x 120 frame through the inverse and back. */
static void round_trip(const char *model, const double *q, int np) {
    ws_lens lens;
    ws_status st = {0};
    CHECK(ws_lens_from_colmap(&lens, model, q, np, 160, 120, "rt", &st) == WS_OK, "%s", st.msg);
    double worst = 0;
    int failures = 0;
    for (int i = 0; i < 120; i++)
        for (int j = 0; j < 160; j++) {
            double xd = (j + 0.5 - lens.cx) / lens.fx, yd = (i + 0.5 - lens.cy) / lens.fy, x, y, a, b;
            if (ws_lens_undistort(&lens, xd, yd, &x, &y)) {
                failures++;
                continue;
            }
            ws_lens_distort(&lens, x, y, &a, &b);
            worst = fmax(worst, hypot((a - xd) * lens.fx, (b - yd) * lens.fy));
        }
    CHECK(failures == 0 && worst < 1e-9, "%s: %d pixels without inverse, round trip %g px", model,
          failures, worst);
}

/* Every point of the frame's border, corners included, has an inverse
 * with tangential terms (which move the corner's ray off the radial
 * profile the one-to-one range is walked along): the pinhole canvas of a
 * lens render exists. */
static void border(void) {
    const double q[8] = {300, 300, 201.6, 151.2, -0.1, 0.02, 0.001, -0.0005};
    ws_lens lens;
    ws_status st = {0};
    int w = 0, h = 0;
    double K[4];
    CHECK(ws_lens_from_colmap(&lens, "OPENCV", q, 8, 403, 302, "b", &st) == WS_OK &&
              ws_lens_canvas(&lens, 2, &w, &h, K, &st) == WS_OK && w > 806 && h > 604,
          "border: %s (canvas %d x %d)", st.msg, w, h);
}

static void refusals(void) {
    ws_lens lens;
    ws_status st = {0};
    const double q[8] = {100, 100, 80, 60, -0.9, 0, 0, 0};
    CHECK(ws_lens_from_colmap(&lens, "OPENCV", q, 8, 160, 120, "cameras.txt: camera 1", &st) ==
                  WS_EINPUT &&
              !strcmp(st.msg, "cameras.txt: camera 1: lens distortion folds the image (the "
                              "distorted radius stops growing at 41 px from the principal point, "
                              "inside the frame, whose corner is 100 px out)"),
          "fold: %s", st.msg);
    CHECK(ws_lens_from_colmap(&lens, "THIN_PRISM_FISHEYE", q, 8, 160, 120, "c", &st) == WS_EINPUT &&
              !strcmp(st.msg, "c: unknown camera model 'THIN_PRISM_FISHEYE' (SIMPLE_PINHOLE, "
                              "PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, OPENCV_FISHEYE or "
                              "FULL_OPENCV)"),
          "unknown: %s", st.msg);
    CHECK(ws_lens_from_colmap(&lens, "RADIAL", q, 4, 160, 120, "c", &st) == WS_EINPUT &&
              !strcmp(st.msg, "c: camera model RADIAL takes 5 parameters, not 4"),
          "count: %s", st.msg);
    const double tangential[8] = {100, 100, 80, 60, 0, 0, 0.6, 0};
    CHECK(ws_lens_from_colmap(&lens, "OPENCV", tangential, 8, 160, 120, "c", &st) == WS_EINPUT &&
              !strncmp(st.msg, "c: lens distortion folds the image (its Jacobian is not positive",
                       62),
          "tangential fold: %s", st.msg);
    const double pincushion[8] = {100, 100, 80, 60, 0.3, 0.1, 0.001, 0};
    CHECK(ws_lens_from_colmap(&lens, "OPENCV", pincushion, 8, 160, 120, "c", &st) == WS_OK,
          "a strong but one-to-one lens is accepted: %s", st.msg);
}

int main(void) {
    reference_points();
    const double opencv[8] = {120, 118, 81.5, 58.25, -0.3, 0.09, 0.002, -0.001};
    const double full[12] = {120, 121, 80, 60, -0.3, 0.1, 0.001, -0.0005, -0.01, 0.05, 0.01, 0.002};
    const double fisheye[8] = {60, 60, 80, 60, 0.05, -0.01, 0.003, -0.0005};
    const double radial[5] = {110, 79, 61, -0.2, 0.04};
    round_trip("OPENCV", opencv, 8);
    round_trip("FULL_OPENCV", full, 12);
    round_trip("OPENCV_FISHEYE", fisheye, 8);
    round_trip("RADIAL", radial, 5);
    border();
    refusals();
    return check_summary();
}
