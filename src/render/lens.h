/* lens.h: lens distortion models (METHOD.md, "Lens models"), forward and
 * exact inverse.
 *
 * COLMAP's camera models, in OpenCV's normalised coordinates (x, y) =
 * (X / Z, Y / Z) of a camera-space point (x right, y down, z forward),
 * r^2 = x^2 + y^2, image point u = fx x_d + cx, v = fy y_d + cy:
 *   SIMPLE_PINHOLE  f, cx, cy                       no distortion
 *   PINHOLE         fx, fy, cx, cy                  no distortion
 *   SIMPLE_RADIAL   f, cx, cy, k                    radial 1 + k r^2
 *   RADIAL          f, cx, cy, k1, k2               radial 1 + k1 r^2 + k2 r^4
 *   OPENCV          fx, fy, cx, cy, k1, k2, p1, p2  radial, tangential
 *   FULL_OPENCV     fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6
 *                   radial (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2 + k5 r^4 + k6 r^6)
 *   OPENCV_FISHEYE  fx, fy, cx, cy, k1, k2, k3, k4  theta = atan r,
 *                   theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
 *                   (x_d, y_d) = theta_d / r (x, y)
 * Perspective models: x_d = x radial + 2 p1 x y + p2 (r^2 + 2 x^2),
 * y_d = y radial + p1 (r^2 + 2 y^2) + 2 p2 x y. nerfstudio and instant-ngp
 * name the same with keys (k1..k4, p1, p2, is_fisheye), their perspective
 * radial being the polynomial 1 + k1 r^2 + k2 r^4 + k3 r^6 + k4 r^8. Pixel
 * centres are at integer + 1/2, as in COLMAP and camera.h. */
#ifndef WS_LENS_H
#define WS_LENS_H
#include "nn/base/status.h"

typedef struct {
    double fx, fy, cx, cy; /* pixels */
    int width, height;     /* the frame */
    int fisheye;           /* 1: OPENCV_FISHEYE's angle polynomial */
    double k[4];           /* perspective: radial numerator's r^2..r^8 terms;
                              fisheye: theta_d's theta^2..theta^8 terms */
    double kd[3];          /* perspective: radial denominator's r^2..r^6 terms */
    double p[2];           /* tangential p1, p2 (perspective) */
    double r_max;          /* normalised undistorted radius up to which the
                              distortion is one-to-one and covers the frame
                              (set by ws_lens_check) */
} ws_lens;

/* The COLMAP model names, in COLMAP's model id order (0..6). */
extern const char *const ws_lens_model_names[];
extern const int ws_lens_model_count;
/* How many parameters each of them takes (COLMAP's order). */
extern const int ws_lens_model_params[];

/* The lens of COLMAP model `model` (a name of ws_lens_model_names) with
 * its parameters, for a width x height frame; then ws_lens_check. Fails
 * with "WHAT: unknown camera model 'M' (...)" or "WHAT: camera model M
 * takes N parameters, not n". */
int ws_lens_from_colmap(ws_lens *lens, const char *model, const double *params, int nparams,
                        int width, int height, const char *what, ws_status *st);

/* The COLMAP model (index into ws_lens_model_names) and parameters that
 * state `lens`: PINHOLE, OPENCV, FULL_OPENCV or OPENCV_FISHEYE; -1 when
 * none can (a perspective r^8 term, nerfstudio's k4). params: 12 doubles. */
int ws_lens_to_colmap(const ws_lens *lens, double *params);

/* 1 when the lens has no distortion. */
int ws_lens_is_pinhole(const ws_lens *lens);

/* Checks that the lens is usable over its frame: finite values, positive
 * focal lengths, and a distortion that is one-to-one from the image centre
 * out to the frame's farthest corner (radially increasing, Jacobian
 * determinant positive); sets r_max. A lens that folds the image fails
 * with "WHAT: lens distortion folds the image (...)". */
int ws_lens_check(ws_lens *lens, const char *what, ws_status *st);

/* Forward: normalised undistorted (x, y) to normalised distorted. */
void ws_lens_distort(const ws_lens *lens, double x, double y, double *xd, double *yd);

/* Inverse: the normalised (x, y) with distortion (xd, yd), within r_max,
 * by Newton's method to 1e-12; -1 (and x, y where it stopped) when there
 * is none. */
int ws_lens_undistort(const ws_lens *lens, double xd, double yd, double *x, double *y);

#endif
