/* camera.c: pinhole cameras (see camera.h). */
#include <math.h>
#include "render/camera.h"

int ws_camera_init(ws_camera *cam, const double c2w[4][4], double camera_angle_x,
                   int width, int height, const char *what, ws_status *st) {
    if (ws_camera_check_angle(camera_angle_x, what, st)) return st->code;
    return ws_camera_init_pinhole(cam, c2w, 0.5 * width / tan(0.5 * camera_angle_x), 0.5 * width,
                                  0.5 * height, width, height, what, st);
}

int ws_camera_init_pinhole(ws_camera *cam, const double c2w[4][4], double focal, double cx,
                           double cy, int width, int height, const char *what, ws_status *st) {
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            if (!isfinite(c2w[i][j]))
                return ws_fail(st, WS_EINPUT, "%s: transform_matrix has a non-finite entry", what);
            cam->c2w[i][j] = c2w[i][j];
        }
    if (!(focal > 0) || !isfinite(focal) ||
        ws_camera_check_angle(2 * atan(0.5 * width / focal), what, st))
        return ws_fail(st, WS_EINPUT, "%s: focal length %g pixels at width %d is out of range", what,
                       focal, width);
    if (!isfinite(cx) || !isfinite(cy))
        return ws_fail(st, WS_EINPUT, "%s: principal point (%g, %g) is not finite", what, cx, cy);
    if (c2w[3][0] != 0 || c2w[3][1] != 0 || c2w[3][2] != 0 || c2w[3][3] != 1)
        return ws_fail(st, WS_EINPUT, "%s: transform_matrix's bottom row is not 0 0 0 1", what);
    const double (*a)[4] = c2w;
    /* Inverse of the 3x3 part by cofactors; the scale of the determinant is
     * compared with the matrix's own scale so that tiny scenes are not
     * mistaken for singular ones. */
    double cof[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            cof[i][j] = a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1];
        }
    double det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
    double scale = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) scale = fmax(scale, fabs(a[i][j]));
    if (!(fabs(det) > 1e-9 * scale * scale * scale) || scale == 0)
        return ws_fail(st, WS_EINPUT, "%s: transform_matrix is singular (det %g)", what, det);
    /* A camera-to-world rotation is orthonormal: columns of unit length at
     * right angles. A scaled or sheared one is not a pinhole camera (and a
     * scale of 1e100 overflows every projection), so it is refused. */
    double off = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            off = fmax(off, fabs(a[0][i] * a[0][j] + a[1][i] * a[1][j] + a[2][i] * a[2][j] - (i == j)));
    if (!(off <= WS_CAMERA_ORTHONORMAL_TOLERANCE))
        return ws_fail(st, WS_EINPUT,
                       "%s: transform_matrix's rotation is not orthonormal (R^T R differs from I by %.3g)",
                       what, off);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) cam->R[i][j] = cof[j][i] / det;
    for (int i = 0; i < 3; i++)
        cam->t[i] = -(cam->R[i][0] * a[0][3] + cam->R[i][1] * a[1][3] + cam->R[i][2] * a[2][3]);
    cam->width = width;
    cam->height = height;
    cam->focal = focal;
    cam->cx = cx;
    cam->cy = cy;
    return WS_OK;
}

int ws_camera_check_angle(double camera_angle_x, const char *what, ws_status *st) {
    if (!(camera_angle_x >= WS_CAMERA_MIN_ANGLE && camera_angle_x <= M_PI - WS_CAMERA_MIN_ANGLE))
        return ws_fail(st, WS_EINPUT, "%s: camera_angle_x %g is not in [%g, pi - %g]", what,
                       camera_angle_x, WS_CAMERA_MIN_ANGLE, WS_CAMERA_MIN_ANGLE);
    return WS_OK;
}

void ws_camera_ray(const ws_camera *cam, double u, double v, double dir[3]) {
    dir[0] = (u - cam->cx) / cam->focal;
    dir[1] = -(v - cam->cy) / cam->focal;
    dir[2] = -1.0;
}

void ws_camera_position(const ws_camera *cam, double pos[3]) {
    for (int i = 0; i < 3; i++) pos[i] = cam->c2w[i][3];
}

void ws_camera_pixel_ray(const ws_camera *cam, double i, double j, double D[3]) {
    ws_camera_ray(cam, j + WS_PIXEL_CENTER, i + WS_PIXEL_CENTER, D);
}
