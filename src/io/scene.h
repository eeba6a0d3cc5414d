/* scene.h: multi-view scenes (METHOD.md section 1), in three layouts.
 *
 * NeRF-synthetic: SCENE/transforms_{train,val,test}.json hold
 * camera_angle_x and frames (file_path without extension, 4x4
 * camera-to-world transform_matrix); images are found at
 * SCENE/<file_path>.png or SCENE/rgb/<file_path>.png (a file_path that
 * ends in .png, .jpg or .jpeg is used as written: SCENE/<file_path> or
 * SCENE/rgb/<file_path>; PNG or JPEG, as the content says), resampled whole to
 * the working size. Missing splits are allowed (n = 0), but a scene needs
 * a train split.
 *
 * nerfstudio / instant-ngp, when SCENE/transforms.json
 * exists and SCENE/transforms_train.json does not: one file of frames with
 * pinhole intrinsics fl_x, fl_y, cx, cy, w, h in pixels, global or per
 * frame (a frame's own value wins; fl_y defaults to fl_x, cx and cy to the
 * image centre, and camera_angle_x may stand for fl_x); images of any
 * aspect. The working view is the crop of the image whose aspect makes its
 * pixels square at the working size (fl_x / fl_y times the working aspect:
 * the largest square for fl_x = fl_y and a square working size) around the
 * object's projection (io/view_crop.h), zoomed onto the object's box by
 * ws_scene_zoom, resampled to the working size, with the intrinsics
 * carried along.
 * Splits: train_filenames / val_filenames / test_filenames where the file
 * has them (frames in none are left out); otherwise frame k (in file
 * order) is a test view when k % 8 == 0, a val view when k % 8 == 4, and a
 * train view else. A lens (render/lens.h) from camera_model (PINHOLE,
 * SIMPLE_PINHOLE, OPENCV, OPENCV_FISHEYE; none: OPENCV), instant-ngp's
 * is_fisheye, k1..k4, p1, p2, global or per frame.
 * Either JSON layout's file (the train split's for NeRF-synthetic) may
 * give the object's box as instant-ngp's "aabb" (has_aabb, aabb).
 *
 * COLMAP, when SCENE has neither transforms file: the sparse model at
 * SCENE/sparse/0, SCENE/sparse or SCENE (io/colmap.h; text or binary,
 * several cameras), images SCENE/images/<name> (opt.images_dir/<name>
 * with --images). Each image's world-to-camera pose is converted exactly
 * to camera.h's convention (colmap.h); the world frame is the file's (no
 * re-centring or scaling, so curves land on the user's model). Frames are
 * numbered in name order; splits from SCENE/{train,val,test}_list.txt (one
 * name a line, as nerfstudio reads them) when any exists, else the rule
 * above. The working view is made as for nerfstudio; points3D are kept
 * (ws_scene_points).
 *
 * Photos through a lens are undistorted once, on load, to the pinhole
 * camera of the same fx, fy, cx, cy and size (io/undistort.h), before the
 * crop; so are masks and edge maps.
 *
 * Masks (white = object; the size of their image): a frame's mask_path
 * (JSON layouts, relative to SCENE) wins; else the mask of a masks folder,
 * opt.masks_dir or, for nerfstudio and COLMAP scenes, SCENE/masks where it
 * exists: FOLDER/<image_name> with its image extension replaced by .png or
 * .png added (COLMAP's convention: image.jpg.png). When a masks folder is
 * used, every view without a mask_path must have its mask there.
 *
 * In the JSON layouts a frame's optional mask_path (a PNG, white = object) is
 * relative to SCENE, and so is its optional edge_path (a grayscale PNG, an
 * edge map made elsewhere, e.g. by a learned detector); with
 * opt.edge_maps_dir every view's edge map is instead DIR/<file_path>.png
 * (the photo's own relative name, e.g. DIR/train/r_0.png). Edge maps are read like the photos (resampled to
 * the image's size, cropped, resampled to the working size; first channel,
 * values in [0, 1]). */
#ifndef WS_SCENE_H
#define WS_SCENE_H
#include <limits.h>
#include "render/camera.h"
#include "render/lens.h"
#include "base/paths.h"
#include "base/progress.h"
#include "io/image.h"
#include "io/splits.h"
#include "nn/base/status.h"

typedef struct {
    char name[256];       /* image file name without extension: "r_0" */
    int frame;            /* its index in its transforms file's frames[] (ws_scene_file);
                             a split's views are in this order */
    char image_path[WS_PATH_MAX];/* the PNG that was found */
    ws_camera cam;
    ws_image photo;       /* 3 x height x width, composited on the background */
    char image_name[256]; /* the image's name in its images folder, which its mask in a
                             masks folder repeats: COLMAP's image name; file_path without
                             "./" (nerfstudio: and without its first folder, "images/") */
    char mask_path[WS_PATH_MAX]; /* the mask file: the frame's mask_path, resolved, else the one
                             of a masks folder; "" when it has none */
    ws_image mask;        /* 1 x height x width: 1 = object, 0 = background; from the
                             mask_path image (value >= 1/2 of white) or else the photo's
                             alpha (>= 1/2); data NULL when neither exists (an opaque
                             alpha channel counts as none) */
    int crop[4];          /* x0, y0, width, height: the file's pixels that make the
                             working view; width 0: the whole file (NeRF-synthetic) */
    int file_width, file_height; /* the image size the scene file states; 0: any */
    int reduced;          /* the photo was decoded at 1 / reduced of its file's size a side
                             (io/image.h ws_image_read_reduced); 0 until it is loaded */
    char edge_path[WS_PATH_MAX]; /* the frame's edge_path or --edge-maps file; "" when none */
    ws_image edges;       /* 1 x height x width from edge_path; data NULL when none */
    ws_lens lens;         /* the image file's lens (pinhole: all distortion 0); the
                             photo, mask and edge map are undistorted to the
                             pinhole camera of its fx, fy, cx, cy on load */
} ws_view;

typedef struct {
    int n;
    ws_view *views;
} ws_split;

typedef struct {
    int width, height;     /* working resolution, default 224 x 224 */
    float background[3];   /* alpha is composited onto this, and pixels a mask_path
                              marks as background are set to it; default black */
    int background_auto;   /* 1: instead, each image's own background: the median
                              of its border pixels (composited on black) */
    int load_images;       /* 0: cameras only (e.g. for render) */
    int defer_images;      /* 1: the image files are found but not read: ws_scene_zoom reads them */
    const char *edge_maps_dir; /* NULL, or the directory of every view's edge map */
    const char *images_dir;    /* COLMAP: NULL (SCENE/images), or where the images are */
    const char *masks_dir;     /* NULL (nerfstudio and COLMAP: SCENE/masks where it exists),
                                  or the folder of every view's mask */
    ws_progress *progress;     /* NULL (silent), or where loading the photos and the
                                  scene's later long steps show how far they came */
} ws_scene_options;

enum { WS_LAYOUT_NERF_SYNTHETIC = 0, WS_LAYOUT_NERFSTUDIO = 1, WS_LAYOUT_COLMAP = 2 };

typedef struct {
    char dir[PATH_MAX];    /* the directory as given (a user's path: paths made from it are WS_PATH_MAX) */
    int layout;            /* WS_LAYOUT_... */
    double camera_angle_x; /* of the train split (its first view's, at the working size) */
    int width, height;
    ws_split split[WS_NSPLITS];
    double center[3];      /* least-squares intersection of the optical axes */
    char model_file[WS_PATH_MAX]; /* COLMAP: the images file, relative to dir
                              ("sparse/0/images.txt") */
    int masks_from_paths;  /* views whose mask is their frame's mask_path */
    int masks_from_dir;    /* views whose mask is in masks_dir */
    char masks_dir[WS_PATH_MAX]; /* the masks folder used; "" when none */
    int has_aabb;          /* 1: the transforms file (nerfstudio's, or the train split's) has
                              instant-ngp's "aabb" (io/transforms.h) */
    double aabb[2][3];     /* that box, lo then hi, in the file's world frame */
    int npoints;           /* COLMAP's points3D, or nerfstudio's ply_file_path, in the file's
                              world frame */
    double *points;        /* npoints x 3; NULL when the scene has none */
    char points_missing[WS_PATH_MAX]; /* the ply_file_path a nerfstudio file names when no
                                         such file is there; "" otherwise */
    int zoomed;            /* views whose crop zooms onto the object's box (ws_scene_zoom):
                              smaller than their frame's largest crop */
    ws_progress *progress; /* the options' (borrowed): the long steps made on this scene
                              (the photo hull, the views' vote) show their progress there */
} ws_scene;

void ws_scene_options_default(ws_scene_options *opt);
/* Loads every split (images decoded in parallel). A malformed input fails
 * with one line naming the file and, for a frame, its index in frames[]
 * from 0: "SCENE/transforms_train.json: frame 3: transform_matrix is not
 * 4x4"; image errors name the PNG. The centre uses the cameras of all
 * splits; when their axes are (nearly) parallel, the least-squares problem
 * has no single answer and the centroid of each axis' point nearest the
 * mean camera position is used instead. */
int ws_scene_load(ws_scene *scene, const char *dir, const ws_scene_options *opt, ws_status *st);
/* The second half of a load that zooms (geometry/roi.h ws_roi_load_scene):
 * a scene loaded with opt.defer_images (or without images) gets every
 * nerfstudio or COLMAP view's crop zoomed onto the object's box (lo then
 * hi; io/view_crop.h; NULL: the crops stay), then, when opt->load_images,
 * its masks and photos, cut by those crops. A NeRF-synthetic scene's views
 * stay whole. Frees the scene on failure. */
int ws_scene_zoom(ws_scene *scene, const double box[6], const ws_scene_options *opt, ws_status *st);
void ws_scene_free(ws_scene *scene);

/* The transforms file (in scene->dir) that lists split s's frames:
 * "transforms_train.json" etc., "transforms.json" for every split of a
 * nerfstudio scene, the images file (scene->model_file) of a COLMAP one. */
const char *ws_scene_file(const ws_scene *scene, int s);

/* The line that says where the masks came from ("SCENE: masks for 56 of
 * 64 views from DIR"), "" when no view has a mask file. */
void ws_scene_mask_line(const ws_scene *scene, char *line, size_t size);

/* The scene's sparse points (COLMAP's points3D, or the PLY file a
 * nerfstudio file names as ply_file_path, as the file has them, outliers
 * included): *n of them, x y z each; NULL with *n = 0 when the
 * scene has none. */
const double *ws_scene_points(const ws_scene *scene, int *n);

/* "train" -> WS_TRAIN etc.; -1 for anything else. */
int ws_split_index(const char *name);

#endif
