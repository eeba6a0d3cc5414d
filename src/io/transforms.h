/* transforms.h: the transforms JSON, read and written; the one owner of
 * the format (scene.h says how a scene is made of it, METHOD.md section 1).
 *
 * Two kinds of file:
 *   NeRF-synthetic, SCENE/transforms_SPLIT.json: camera_angle_x, and frames
 *     (file_path, optional mask_path and edge_path, a 4x4 camera-to-world
 *     transform_matrix in camera.h's axes);
 *   nerfstudio / instant-ngp, SCENE/transforms.json: every split's frames in
 *     one file, with pinhole intrinsics fl_x, fl_y, cx, cy, w, h (pixels;
 *     camera_angle_x may stand for fl_x), a lens (camera_model PINHOLE,
 *     SIMPLE_PINHOLE, OPENCV or OPENCV_FISHEYE, instant-ngp's is_fisheye,
 *     k1..k4, p1, p2), each global or per frame (a frame's own value wins),
 *     and optional split lists train_filenames / val_filenames /
 *     test_filenames.
 * Either kind may carry instant-ngp's "aabb", the object's box.
 * Files are read whole (at most 64 MiB) and kept parsed while open, so that
 * a frame is found by its index in frames[] at once. */
#ifndef WS_TRANSFORMS_H
#define WS_TRANSFORMS_H
#include "io/splits.h"
#include "render/lens.h"
#include "nn/base/status.h"


enum { WS_TRANSFORMS_SPLIT = 0, WS_TRANSFORMS_NERFSTUDIO = 1 };

/* The files' names in a scene folder: split s's file of a NeRF-synthetic
 * scene ("transforms_train.json"...), a nerfstudio scene's one file. */
extern const char *const ws_transforms_split_files[WS_NSPLITS];
#define WS_TRANSFORMS_FILE "transforms.json"

typedef struct ws_transforms ws_transforms;

/* One frame: its paths as the file writes them (relative to the scene)
 * and its camera-to-world matrix. Read: strings owned by the open file,
 * mask_path and edge_path NULL when absent. Written: mask_path and
 * edge_path when not NULL; split names the nerfstudio split list the frame
 * is in (WS_TRAIN...). */
typedef struct {
    const char *file_path, *mask_path, *edge_path;
    double c2w[4][4];
    int split;
} ws_transforms_frame;

/* A frame's pinhole intrinsics and lens (nerfstudio), the lens carrying
 * the same fx, fy, cx, cy and size. */
typedef struct {
    double fx, fy, cx, cy;
    int w, h;
    ws_lens lens;
} ws_transforms_camera;

/* Reads and parses `path` as `kind`: a JSON object (else "PATH: JSON
 * syntax error near line N" or "PATH: not a JSON object") with, for a
 * split file, a valid camera_angle_x, and a non-empty array of frames no
 * longer than WS_MAX_VIEWS. */
int ws_transforms_open(ws_transforms **t, const char *path, int kind, ws_status *st);
void ws_transforms_close(ws_transforms *t);

int ws_transforms_count(const ws_transforms *t);       /* frames */
int ws_transforms_kind(const ws_transforms *t);        /* WS_TRANSFORMS_... */
double ws_transforms_angle(const ws_transforms *t);    /* a split file's camera_angle_x */
/* frame k's file_path, "" when it has none or it is not a string */
const char *ws_transforms_file_path(const ws_transforms *t, int k);

/* The file's "aabb" (instant-ngp: [[x0,y0,z0],[x1,y1,z1]], the object's box
 * in the file's world frame; aabb_scale, a scale of instant-ngp's own
 * grid, is no box and not read): *found = 0 when the file has none; else
 * "PATH: aabb is not two triples of finite numbers [[x0,y0,z0],[x1,y1,z1]]"
 * or "PATH: aabb is empty along y (1 >= 0.5)" when it is not a box. */
int ws_transforms_aabb(const ws_transforms *t, double aabb[2][3], int *found, ws_status *st);

/* The file's "ply_file_path" (nerfstudio's sparse points, as ns-process-data
 * writes them: a PLY file relative to the scene's folder, in the file's
 * world frame): *name NULL when the file has none; fails with "PATH:
 * ply_file_path is not a file name" when it is not a non-empty string. */
int ws_transforms_ply_file(const ws_transforms *t, const char **name, ws_status *st);

/* Each frame's split (nerfstudio): by the split lists where the file has
 * any (a frame in none: -1; a file_path matched after any "./"), else by
 * ws_transforms_split_rule. split_of holds ws_transforms_count entries. */
int ws_transforms_splits(const ws_transforms *t, int *split_of, ws_status *st);

/* Frame k of a file without split lists: test when k % 8 == 0, val when
 * k % 8 == 4, train else (nerfstudio's rule; COLMAP scenes follow it too). */
int ws_transforms_split_rule(int k);

/* Frame k's paths and matrix; messages start with `what` ("PATH: frame
 * 3: missing transform_matrix"). */
int ws_transforms_frame_read(const ws_transforms *t, int k, const char *what, ws_transforms_frame *f,
                             ws_status *st);

/* Frame k's intrinsics and lens (nerfstudio): a frame's own value, else
 * the file's; fl_y defaults to fl_x, cx and cy to the image centre. */
int ws_transforms_camera_read(const ws_transforms *t, int k, const char *what, ws_transforms_camera *cam,
                              ws_status *st);

/* Writes a NeRF-synthetic split file: camera_angle_x, object_position
 * (the point the cameras look at) and the n frames. */
int ws_transforms_write_split(const char *path, double camera_angle_x, const double object_position[3],
                              const ws_transforms_frame *frames, int n, ws_status *st);

/* Writes a nerfstudio file: the global intrinsics and lens of `cam`
 * (camera_model OPENCV with k1, k2, p1, p2, and k3, k4 where not 0;
 * OPENCV_FISHEYE with k1..k4), ply_file_path where not NULL, the split
 * lists, and the n frames. */
int ws_transforms_write_nerfstudio(const char *path, const ws_transforms_camera *cam, const char *ply_file_path,
                                   const ws_transforms_frame *frames, int n, ws_status *st);

/* The changes ws_transforms_rewrite makes to an open file's n frames. */
typedef struct {
    const int *camera;  /* frame k takes the transform_matrix of frame camera[k] (k: its own) */
    const char *flip;   /* frames whose matrix turns from OpenCV's camera axes to camera.h's
                           (y and z negated) */
    const char *drop;   /* frames left out */
    double focal_scale; /* fl_x, fl_y, and camera_angle_x's focal, of the file and of every
                           frame, times this */
    const int *split_of;/* each frame's split (-1: in none): a nerfstudio file that drops
                           frames lists every split's frames explicitly, so that the k % 8
                           rule does not move the frames after a dropped one */
} ws_transforms_edit;

/* Writes the open file with the edit to out_path (everything else, keys
 * unknown to wiresketch included, as it was). */
int ws_transforms_rewrite(const ws_transforms *t, const ws_transforms_edit *e, const char *out_path,
                          ws_status *st);

/* Is `name` (a scene folder's entry) a camera file of this format:
 * transforms_*, and for a nerfstudio scene transforms.json too? */
int ws_transforms_is_file(const char *name, int nerfstudio);

#endif
