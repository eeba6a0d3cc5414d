/* view_crop.h: the working view of a frame of any size and aspect, with its
 * principal point anywhere (issue 22, item 3).
 *
 * The working view is a crop of the frame whose pixels come out square at
 * the working size W x H (crop cw x ch resampled to W x H gives focal
 * lengths fl_x W / cw and fl_y H / ch, equal when cw / ch = (fl_x / fl_y)
 * (W / H); whole pixels, so that equality holds to half a pixel of the
 * crop; the camera's one focal is the geometric mean of the two). Without
 * an object box it is the largest such crop, placed so that the projection
 * of the scene's centre (where the cameras look: the object) is as near its
 * middle as the frame allows, not the frame's centre: an object off-centre
 * in a portrait or landscape frame keeps its parts. With the object's box
 * (the region of interest, geometry/roi.h) it zooms in: the smallest such
 * crop that holds the box's projection with WS_VIEW_CROP_MARGIN of its
 * extent on every side, around that projection's middle; never smaller than
 * W x H pixels (a working pixel is never less than a frame pixel, so
 * nothing is magnified) nor larger than the largest crop. A small object in
 * a large frame then fills the working view as it fills a render's. The
 * principal point moves with the crop and scales with it. */
#ifndef WS_IO_VIEW_CROP_H
#define WS_IO_VIEW_CROP_H
#include "render/camera.h"
#include "nn/base/status.h"

/* The box then spans at most 1/1.6 of the working view, about what objects
 * span in the renders the line loss was tuned on; held tighter, a wire's
 * tube a few pixels wide becomes two outlines (METHOD.md section 17). */
#define WS_VIEW_CROP_MARGIN 0.3

/* The crop (x0, y0, width, height in the frame's pixels) and the working
 * camera of a frame of w x h pixels with pinhole intrinsics fx, fy, cx, cy
 * (pixels) and camera-to-world c2w; working size W x H. box (lo then hi;
 * NULL, or a box not wholly in front of the camera: none) zooms onto the
 * object's box, else the largest crop is placed around the projection of
 * `target` (NULL, or a target behind the camera: around the frame's
 * centre). Fails like ws_camera_init_pinhole, with `what` naming the
 * frame. */
int ws_view_crop(double fx, double fy, double cx, double cy, int w, int h, const double c2w[4][4],
                 const double target[3], const double box[6], int W, int H, const char *what, int crop[4],
                 ws_camera *cam, ws_status *st);

#endif
