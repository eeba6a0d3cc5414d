/* colmap.h: COLMAP sparse models, text and binary, read and written
 * (METHOD.md, "Lens models" and "COLMAP's cameras").
 *
 * A model is three files in one folder: cameras (id, model, width, height,
 * parameters: render/lens.h), images (id, world-to-camera rotation as a
 * quaternion qw qx qy qz and translation t in OpenCV axes, camera id,
 * file name; each followed by its 2D points, which are skipped) and
 * points3D (id, x y z, colour, error, track). `.txt` and `.bin` are both
 * read (text first when a folder holds both), following COLMAP's
 * src/colmap/scene/reconstruction_io.cc. */
#ifndef WS_COLMAP_H
#define WS_COLMAP_H
#include <stddef.h>
#include "render/lens.h"
#include "io/splits.h"
#include "nn/base/status.h"

typedef struct {
    int id;
    ws_lens lens; /* intrinsics, distortion and frame size */
} ws_colmap_camera;

typedef struct {
    int id, camera_id;
    double q[4]; /* qw, qx, qy, qz: world-to-camera rotation, OpenCV axes */
    double t[3]; /* world-to-camera translation */
    char name[256];
} ws_colmap_image;

typedef struct {
    int ncameras, nimages, npoints;
    ws_colmap_camera *cameras;
    ws_colmap_image *images;
    double *points; /* npoints x 3, world frame */
} ws_colmap_model;

/* The folder of a model under dir: dir/sparse/0, dir/sparse or dir, the
 * first holding cameras.txt or cameras.bin, into `found`; 0 when there is
 * one, -1 when none (no message: the caller says what it looked for). */
int ws_colmap_find(const char *dir, char *found, size_t size);

/* Reads the model in `folder`. One-line failures name the file and the
 * record: "F/cameras.txt: line 4: unknown camera model 'FOV' (...)",
 * "F/images.bin: truncated (ends inside image 3 of 10)",
 * "F/points3D.txt: line 9: point 17: coordinate is not finite",
 * "F/images.txt: line 5: image 2: camera 7 is not in cameras.txt". */
int ws_colmap_read(ws_colmap_model *m, const char *folder, ws_status *st);
void ws_colmap_free(ws_colmap_model *m);

/* The camera of image `im`, or NULL. */
const ws_colmap_camera *ws_colmap_camera_of(const ws_colmap_model *m, const ws_colmap_image *im);

/* COLMAP's world-to-camera (q, t; OpenCV axes: x right, y down, z
 * forward) as the camera-to-world matrix of camera.h (Blender/OpenGL
 * axes: y up, z backward): c2w = [R^T F | -R^T t], F = diag(1, -1, -1). */
void ws_colmap_to_c2w(const double q[4], const double t[3], double c2w[4][4]);

/* The inverse: q (qw >= 0, unit) and t of a camera-to-world matrix. */
void ws_colmap_from_c2w(const double c2w[4][4], double q[4], double t[3]);

/* A COLMAP scene's split lists, SCENE/{train,val,test}_list.txt: one image
 * name a line, as nerfstudio's COLMAP loader reads them. text[s] is split
 * s's file (WS_TRAIN...), NULL when absent; any: one of them exists. */
typedef struct {
    char *text[WS_NSPLITS];
    int any;
} ws_colmap_lists;

int ws_colmap_lists_read(const char *dir, ws_colmap_lists *l, ws_status *st);
void ws_colmap_lists_free(ws_colmap_lists *l);

/* The split whose list names image `name`, -1 when none does. */
int ws_colmap_lists_split(const ws_colmap_lists *l, const char *name);

/* Writes the three list files into dir: image k (names[k]) in the list
 * of split split_of[k]. */
int ws_colmap_lists_write(const char *dir, const char *const *names, const int *split_of, int n, ws_status *st);

/* Writes the model into `folder` (which must exist) as text (binary = 0)
 * or binary, each file through a temporary name (outfile.h). */
int ws_colmap_write(const ws_colmap_model *m, const char *folder, int binary, ws_status *st);

#endif
