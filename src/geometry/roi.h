/* roi.h: the region of interest of a capture, an axis-aligned box in the
 * scene's world frame that holds the object and little else, found from
 * what the files give, in this order:
 *   1. the user's box (`fit --bbox x0,y0,z0,x1,y1,z1`);
 *   2. the box the transforms file gives (instant-ngp's "aabb", scene.h),
 *      as it is written;
 *   3. the sparse points (COLMAP's points3D, or the PLY a nerfstudio file
 *      names as ply_file_path; scene.h) with their outliers removed:
 *      the points seen by at least half of the train views (in front, in
 *      the frame), then those whose WS_ROI_NEIGHBOURS-th nearest neighbour
 *      lies within WS_ROI_DENSITY times the median of that distance (a
 *      reconstruction's points crowd along the object's edges; outliers
 *      lie alone), their bounding box grown by WS_ROI_MARGIN of its largest
 *      side on every side; when fewer than WS_ROI_MIN_POINTS remain, 4.;
 *   4. where the cameras look: the cube around the scene's centre (the
 *      least-squares intersection of the optical axes, scene.h) whose half
 *      side is the radius of the largest ball around it that every train
 *      view sees whole (the object is in every view; the room around it
 *      is not in the ball); its line names a nerfstudio file's sparse
 *      points when they were named but not there.
 * A box room's walls and floor (synth/room.h) lie outside every one of
 * these for the capture bed's scenes: the cameras stand 4 from the centre
 * and see a ball of radius about 1.1 there, the object is about 1.5 wide. */
#ifndef WS_ROI_H
#define WS_ROI_H
#include "io/scene.h"
#include "nn/base/status.h"

#define WS_ROI_NEIGHBOURS 8
#define WS_ROI_DENSITY 3.0
#define WS_ROI_MARGIN 0.05
#define WS_ROI_MIN_POINTS 16
#define WS_ROI_MAX_SAMPLE 4096 /* points the outlier test looks at (evenly spaced in the file's order) */
#define WS_ROI_LINE 512

typedef enum { WS_ROI_USER, WS_ROI_AABB, WS_ROI_POINTS, WS_ROI_CAMERAS } ws_roi_source;

typedef struct {
    double lo[3], hi[3];
    ws_roi_source source;
    char line[WS_ROI_LINE]; /* one line: the box and where it came from */
} ws_roi;

/* "x0,y0,z0,x1,y1,z1" into box (lo then hi); WS_EUSAGE naming --bbox when
 * it is not six finite numbers with x0 < x1, y0 < y1, z0 < z1. */
int ws_roi_parse_bbox(const char *text, double box[6], ws_status *st);

/* The middle of the region's box, the point its views' directions are
 * taken from (geometry/view_spread.h). */
void ws_roi_centre(const ws_roi *roi, double centre[3]);

/* The scene's region of interest: from user (a box as ws_roi_parse_bbox
 * makes it) when not NULL, else as above. Fails with WS_EINPUT when the
 * scene's centre is in no train view. */
int ws_roi_find(const ws_scene *scene, const double *user, ws_roi *roi, ws_status *st);

/* Loads the scene in dir (io/scene.h) with every working view of a
 * nerfstudio or COLMAP scene zoomed onto its region of interest
 * (ws_scene_zoom; user as for ws_roi_find) when that region places the
 * object (the user's box, the file's aabb or the sparse points; where the
 * cameras look is only a guess, and zooms nothing), so that a small object
 * in a large frame fills the working view; every command that loads a
 * scene loads it so, and crops it the same way. The region is found on the
 * views' first crops (around the scene's centre, before the zoom), and
 * *roi receives it when not NULL. When it cannot be found (the scene's
 * centre is in no train view) the views stay unzoomed and *roi_st (when
 * not NULL; else ignored) holds the failure, for whoever needs the region
 * to report; it is cleared otherwise. Fails as ws_scene_load does. */
int ws_roi_load_scene(ws_scene *scene, const char *dir, const ws_scene_options *opt, const double *user,
                      ws_roi *roi, ws_status *roi_st, ws_status *st);

/* The sources one at a time (ws_roi_find's 3. and 4.); points: n x 3.
 * ws_roi_from_points sets *found to 0 and leaves roi alone when fewer than
 * WS_ROI_MIN_POINTS pass; it fails only when out of memory. */
int ws_roi_from_points(const ws_scene *scene, const double *points, int n, ws_roi *roi, int *found,
                       ws_status *st);
int ws_roi_from_cameras(const ws_scene *scene, ws_roi *roi, ws_status *st);

#endif
