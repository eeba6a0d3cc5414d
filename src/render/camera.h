/* camera.h: a pinhole camera of a NeRF-synthetic scene (METHOD.md section 3).
 *
 * Blender/OpenGL axes: the camera looks down its -z, +y is up, +x right.
 * A world point p maps to c = R p + t, depth d = -c_z, and image point
 * u = cx + f c_x / d (across), v = cy - f c_y / d (down), where the
 * principal point (cx, cy) is (W/2, H/2) in a NeRF-synthetic scene and
 * anywhere a capture's intrinsics put it (scene.h); pixels are square
 * (one focal f for both axes: a scene with fl_x != fl_y is resampled so
 * that they are). Pixel (row i,
 * column j) is the unit square [j, j+1] x [i, i+1], its centre at
 * (u, v) = (j + 1/2, i + 1/2), where Blender puts it. Everything that maps
 * between the world and pixels goes through ws_camera_project and
 * ws_camera_ray, so this convention lives here alone. */
#ifndef WS_CAMERA_H
#define WS_CAMERA_H
#include "nn/base/status.h"

typedef struct {
    double c2w[4][4]; /* camera-to-world, as in the scene file */
    double R[3][3];   /* world-to-camera rotation (inverse of c2w's 3x3) */
    double t[3];      /* world-to-camera translation */
    double focal;     /* pixels: (width / 2) / tan(camera_angle_x / 2) */
    double cx, cy;    /* principal point, image coordinates: (width / 2, height / 2) */
    int width, height;
} ws_camera;

/* The field of view a camera may have: at least 1 mrad (a focal length of
 * 2 million pixels at 4096 wide), at most pi - 1 mrad; and how far R^T R of
 * its rotation may be from I (float rounding of stored matrices is 1e-7). */
#define WS_CAMERA_MIN_ANGLE 1e-3
#define WS_CAMERA_ORTHONORMAL_TOLERANCE 1e-3

/* Builds a camera from a camera-to-world matrix. Fails with WS_EINPUT (the
 * message starts with `what`, e.g. "transforms_train.json: frame 3") when the
 * matrix is not finite, its bottom row is not 0 0 0 1, it is singular or its
 * rotation is not orthonormal, or the angle is out of range. */
int ws_camera_init(ws_camera *cam, const double c2w[4][4], double camera_angle_x,
                   int width, int height, const char *what, ws_status *st);

/* The same from intrinsics in pixels: focal length, principal point (cx,
 * cy); the focal must give an angle in range and (cx, cy) be finite. */
int ws_camera_init_pinhole(ws_camera *cam, const double c2w[4][4], double focal, double cx,
                           double cy, int width, int height, const char *what, ws_status *st);

/* camera_angle_x in [WS_CAMERA_MIN_ANGLE, pi - WS_CAMERA_MIN_ANGLE]. */
int ws_camera_check_angle(double camera_angle_x, const char *what, ws_status *st);

/* Camera-space coordinates c = R p + t. Inline, as is ws_camera_project:
 * the hull (geometry/hull.c) calls both per voxel and view. */
static inline void ws_camera_to_cam(const ws_camera *cam, const double p[3], double c[3]) {
    for (int i = 0; i < 3; i++)
        c[i] = cam->R[i][0] * p[0] + cam->R[i][1] * p[1] + cam->R[i][2] * p[2] + cam->t[i];
}

/* Pixel j's centre is at image coordinate j + WS_PIXEL_CENTER. */
#define WS_PIXEL_CENTER 0.5

/* Image point (u, v) of camera-space point c; returns its depth d = -c_z.
 * u and v are meaningful only when d > 0. */
static inline double ws_camera_project(const ws_camera *cam, const double c[3], double *u, double *v) {
    double d = -c[2];
    *u = cam->cx + cam->focal * c[0] / d;
    *v = cam->cy - cam->focal * c[1] / d;
    return d;
}

/* Camera-space direction (x, y, -1) of the ray through image point (u, v). */
void ws_camera_ray(const ws_camera *cam, double u, double v, double dir[3]);

/* Camera centre in world space (the translation column of c2w). */
void ws_camera_position(const ws_camera *cam, double pos[3]);

/* Direction D (camera space, D_z = -1, so that the depth along the ray is
 * its parameter) of the ray through the image point at row i, column j in
 * pixel units, where integer (i, j) is the centre of pixel (i, j) under
 * the convention above, and i + 0.25 lies a quarter pixel below it.
 * Renderers (synth) cast their rays through it and so follow the
 * convention wherever it is defined. */
void ws_camera_pixel_ray(const ws_camera *cam, double i, double j, double D[3]);

#endif
