/* synth.h: synthetic test scenes whose ground truth is exactly a curve file.
 *
 * An object is a set of cubic Bezier curves drawn as tubes of one radius
 * (a trefoil knot, a wire chair, a wire spring, a flat paper clip in a
 * tilted plane), or a solid with sharp edges (solids.h: a
 * cube, a dodecahedron, a nut). ws_synth_write renders it from cameras on
 * a sphere around the object into a NeRF-synthetic scene:
 *   DIR/transforms_{train,val,test}.json  (camera_angle_x, frames[])
 *   DIR/rgb/{train,val,test}/r_K.png      (RGB, object on black or white)
 *   DIR/gt_curves.json                    (the tubes' curves, thickness = tube
 *                                          radius; a solid's sharp edges)
 *   DIR/gt_points.ply                     (solids: 20,000 surface points)
 * or, with opt.nerfstudio, in the nerfstudio layout: DIR/transforms.json
 * (fl_x, fl_y, cx, cy, w, h, k1, k2, p1, p2, frames[] with file_path
 * "rgb/SPLIT/r_K.png", train/val/test_filenames) and the same images,
 * which may be width x height, with the principal point off the centre;
 * or, with opt.colmap, as COLMAP writes a
 * capture: DIR/sparse/0/{cameras,images,points3D}.{bin,txt} (one OPENCV
 * camera; points3D: points along the ground-truth curves with noise, and
 * outliers, as a reconstruction's are), DIR/images/SPLIT/r_KKKKK.png and
 * DIR/{train,val,test}_list.txt. opt.jpeg writes the images as JPEG;
 * opt.lens renders them through a lens (render/lens.h: a pinhole render
 * at twice the resolution, resampled through the lens' inverse). The focal
 * length fits the field of view to the shorter side, so the square of a
 * wide image around its principal point is the square image of the same
 * camera.
 * Train cameras lie on a Fibonacci spiral over the upper hemisphere, val and
 * test cameras at random (seeded) positions of that hemisphere. Same name,
 * options and seed give the same bytes. */
#ifndef WS_SYNTH_H
#define WS_SYNTH_H
#include <stdint.h>
#include "render/camera.h"
#include "render/curves.h"
#include "base/progress.h"
#include "io/image.h"
#include "io/scene.h"
#include "synth/line_drawing.h"
#include "nn/base/status.h"

typedef struct {
    int views[WS_NSPLITS]; /* views per split [48, 8, 8]; 0 leaves val or test out */
    int size;              /* square image side in pixels [224] */
    uint64_t seed;         /* camera placement [0] */
    int white_background;  /* 1: the object on white instead of black [0] */
    int room;              /* 1: the object in a box room instead (room.h) [0] */
    int on_floor;          /* 1 (with room): the room's floor under the object's lowest
                              point, the object standing on it, not far below [0] */
    int masks;             /* 1: also DIR/masks/SPLIT/r_K.png (white = object; named after
                              the image, as the loader's masks folder: scene.h) and, in the
                              JSON layouts, each frame's mask_path [0] */
    int width, height;     /* a non-square image (nerfstudio layout); 0: size x size */
    double principal[2];   /* the principal point this many pixels right of and below the
                              image centre (nerfstudio layout), so that the object, which
                              the cameras look at, is off-centre as in a crop [0, 0] */
    int nerfstudio;        /* 1: one transforms.json with intrinsics (scene.h) [0] */
    int colmap;            /* 1: a binary COLMAP model instead, 2: a text one [0] */
    int jpeg;              /* 1: the images as JPEG (quality 95), else PNG [0] */
    double lens[4];        /* k1, k2, p1, p2 of the OPENCV lens the views are seen
                              through (nerfstudio and COLMAP layouts) [0] */
    double angle;          /* the field of view across the image's shorter side, radians
                              [Blender's default camera: 0.691]; wider: a smaller object in
                              the frame, as in a phone's photo */
    ws_progress *progress; /* NULL (silent), or where rendering the views shows how far
                              it came (base/progress.h) [NULL] */
} ws_synth_options;

typedef struct {
    ws_curves curves; /* the ground truth; thickness = tube radius */
    double center[3]; /* centre of the curves' bounding box: the cameras look here */
    float colour[3];  /* albedo times light colour */
    int ncapsules;    /* the tubes as capsules around a dense polyline */
    double *capsules; /* ncapsules x 2 endpoints x 3 */
} ws_synth_object;

void ws_synth_options_default(ws_synth_options *opt);

/* Builds object `name`; fails with WS_EUSAGE for an unknown name. */
int ws_synth_object_make(ws_synth_object *obj, const char *name, ws_status *st);
void ws_synth_object_free(ws_synth_object *obj);

/* Renders the object seen by cam into img (allocated here: 3 x cam->height x
 * cam->width): the nearest tube surface of each of supersample^2 rays per
 * pixel, Lambert + ambient shaded, averaged; the background image (3 x
 * height x width, e.g. room.h's) where no tube is hit; g: NULL, or a
 * buffer of the camera's size to fill (supersample odd: line_drawing.h). */
int ws_synth_render(const ws_synth_object *obj, const ws_camera *cam, int supersample,
                    const ws_image *background, ws_image *img, ws_geometry_buffer *g, ws_status *st);

/* Writes the scene of object `name` into directory dir (created if needed). */
int ws_synth_write(const char *name, const char *dir, const ws_synth_options *opt, ws_status *st);

#endif
