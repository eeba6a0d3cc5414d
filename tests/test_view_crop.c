/* test_view_crop.c: the working view's crop of a frame (io/view_crop.h),
 * on a 640 x 480 frame with its principal point off-centre, looking down
 * -z at the origin from 5 units:
 *   - without a box, the largest square crop around the target's
 *     projection, clamped to the frame;
 *   - with the object's box, the smallest crop that holds the box's
 *     projection with WS_VIEW_CROP_MARGIN of its extent on every side,
 *     around its middle, and the working camera maps every point where
 *     the frame's pixels, cut and scaled, put it;
 *   - a tiny box gets a crop of the working size (nothing magnified), one
 *     wider than the frame the largest crop, one behind the camera (or
 *     across its plane) the crop as without a box;
 *   - non-square pixels keep the crop's aspect at fx / fy. */
#include <math.h>
#include <string.h>
#include "check.h"
#include "io/view_crop.h"

enum { FW = 640, FH = 480, W = 64 };
static const double FX = 500, CX = 330, CY = 235;
static const double C2W[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 5}, {0, 0, 0, 1}};
static const double ORIGIN[3] = {0, 0, 0};

static int crop_of(const double *box, double fy, int crop[4], ws_camera *cam) {
    ws_status st;
    ws_status_clear(&st);
    return ws_view_crop(FX, fy, CX, CY, FW, FH, C2W, ORIGIN, box, W, W, "test", crop, cam, &st);
}

static int same_crop(const int a[4], int x0, int y0, int cw, int ch) {
    return a[0] == x0 && a[1] == y0 && a[2] == cw && a[3] == ch;
}

int main(void) {
    int crop[4];
    ws_camera cam, frame;
    ws_status st;
    ws_status_clear(&st);
    ws_camera_init_pinhole(&frame, C2W, FX, CX, CY, FW, FH, "frame", &st);

    /* no box: 480 x 480 around (330, 235), clamped to the frame's top */
    CHECK(crop_of(NULL, FX, crop, &cam) == WS_OK && same_crop(crop, 90, 0, 480, 480), "largest crop %d %d %d %d",
          crop[0], crop[1], crop[2], crop[3]);

    /* a unit cube at the origin: its nearest face (depth 4.5) spans 500 / 4.5 px */
    const double cube[6] = {-0.5, -0.5, -0.5, 0.5, 0.5, 0.5};
    const double extent = FX / 4.5, side = extent * (1 + 2 * WS_VIEW_CROP_MARGIN);
    CHECK(crop_of(cube, FX, crop, &cam) == WS_OK &&
              same_crop(crop, (int)lround(CX - 0.5 * lround(side)), (int)lround(CY - 0.5 * lround(side)),
                        (int)lround(side), (int)lround(side)),
          "zoomed crop %d %d %d %d (side %.2f)", crop[0], crop[1], crop[2], crop[3], side);
    double worst = 0, inside = INFINITY;
    for (int corner = 0; corner < 8; corner++) {
        const double p[3] = {cube[(corner & 1) ? 3 : 0], cube[(corner & 2) ? 4 : 1], cube[(corner & 4) ? 5 : 2]};
        double c[3], u, v, uf, vf;
        ws_camera_to_cam(&cam, p, c);
        ws_camera_project(&cam, c, &u, &v);
        ws_camera_to_cam(&frame, p, c);
        ws_camera_project(&frame, c, &uf, &vf);
        worst = fmax(worst, fmax(fabs(u - (uf - crop[0]) * W / crop[2]), fabs(v - (vf - crop[1]) * W / crop[3])));
        inside = fmin(inside, fmin(fmin(u, W - u), fmin(v, W - v)));
    }
    CHECK(worst < 1e-9, "the working camera is the frame's cut and scaled: off by %g px", worst);
    CHECK(inside >= WS_VIEW_CROP_MARGIN * extent * W / crop[2] - 0.5,
          "the box lies %.2f px inside the working view, want its margin", inside);

    /* a tiny box: a crop of the working size, not smaller */
    const double tiny[6] = {-0.01, -0.01, -0.01, 0.01, 0.01, 0.01};
    CHECK(crop_of(tiny, FX, crop, &cam) == WS_OK && crop[2] == W && crop[3] == W && fabs(cam.focal - FX) < 1e-9,
          "tiny box: crop %d x %d, focal %g", crop[2], crop[3], cam.focal);

    /* wider than the frame, behind the camera, across its plane: as without a box */
    const double wide[6] = {-3, -3, -0.5, 3, 3, 0.5}, behind[6] = {-1, -1, 6, 1, 1, 7},
                 across[6] = {-1, -1, 4, 1, 1, 6};
    CHECK(crop_of(wide, FX, crop, &cam) == WS_OK && same_crop(crop, 90, 0, 480, 480), "wide box %d %d %d %d",
          crop[0], crop[1], crop[2], crop[3]);
    CHECK(crop_of(behind, FX, crop, &cam) == WS_OK && same_crop(crop, 90, 0, 480, 480), "box behind %d %d %d %d",
          crop[0], crop[1], crop[2], crop[3]);
    CHECK(crop_of(across, FX, crop, &cam) == WS_OK && same_crop(crop, 90, 0, 480, 480), "box across %d %d %d %d",
          crop[0], crop[1], crop[2], crop[3]);

    /* fy = 400: crops are 1.25 times as wide as tall, zoomed or not */
    CHECK(crop_of(NULL, 400, crop, &cam) == WS_OK && crop[2] == 600 && crop[3] == 480, "fx / fy: %d x %d", crop[2],
          crop[3]);
    CHECK(crop_of(cube, 400, crop, &cam) == WS_OK && fabs(crop[2] - 1.25 * crop[3]) <= 0.5 && crop[3] < 480,
          "fx / fy zoomed: %d x %d", crop[2], crop[3]);
    return check_summary();
}
