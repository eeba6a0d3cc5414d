/* scene.h: NeRF-synthetic multi-view scenes (METHOD.md section 1).
 *
 * SCENE/transforms_{train,val,test}.json hold camera_angle_x and frames
 * (file_path without extension, 4x4 camera-to-world transform_matrix);
 * images are found at SCENE/<file_path>.png or SCENE/rgb/<file_path>.png;
 * a frame's optional mask_path (a PNG, white = object) is relative to SCENE.
 * Missing splits are allowed (n = 0), but a scene needs a train split. */
#ifndef WS_SCENE_H
#define WS_SCENE_H
#include "render/camera.h"
#include "io/image.h"
#include "nn/base/status.h"

enum { WS_TRAIN = 0, WS_VAL = 1, WS_TEST = 2, WS_NSPLITS = 3 };

typedef struct {
    char name[256];       /* image file name without extension: "r_0" */
    char image_path[4096];/* the PNG that was found */
    ws_camera cam;
    ws_image photo;       /* 3 x height x width, composited on the background */
    char mask_path[4096]; /* the frame's mask_path, resolved; "" when it has none */
    ws_image mask;        /* 1 x height x width: 1 = object, 0 = background; from the
                             mask_path image (value >= 1/2 of white) or else the photo's
                             alpha (>= 1/2); data NULL when neither exists (an opaque
                             alpha channel counts as none) */
} ws_view;

typedef struct {
    int n;
    ws_view *views;
} ws_split;

typedef struct {
    int width, height;     /* working resolution, default 224 x 224 */
    float background[3];   /* alpha is composited onto this, default black */
    int load_images;       /* 0: cameras only (e.g. for render) */
} ws_scene_options;

typedef struct {
    char dir[4096];
    double camera_angle_x; /* of the train split */
    int width, height;
    ws_split split[WS_NSPLITS];
    double center[3];      /* least-squares intersection of the optical axes */
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
void ws_scene_free(ws_scene *scene);

/* "train" -> WS_TRAIN etc.; -1 for anything else. */
int ws_split_index(const char *name);
extern const char *const ws_split_names[WS_NSPLITS];

#endif
