/* hidden_lines.h: hidden-line removal by the training views' visual hull
 * (METHOD.md section 6, "Hidden lines").
 *
 * The stroke image draws every Gaussian in every view, a see-through
 * wireframe, while a solid's photo shows no edge where the solid hides it.
 * With hidden lines removed, a Gaussian is drawn in a view only when the
 * visual hull (geometry/surface.h) does not hide it there:
 *   Z (H x W)  the hull's depth map: every surface voxel, centre p at depth
 *              d, drawn as the disc of radius max(1/2, f rho / d) px
 *              (rho = voxel sqrt(3) / 2, its circumscribed ball) around p's
 *              image point, keeping the smallest d per pixel centre; +inf
 *              where no voxel falls ("no hull there");
 *   T (H x W)  Z plus the tolerance of the voxel that gave Z there:
 *              voxel x min(WS_HIDDEN_TOLERANCE, WS_HIDDEN_TOLERANCE_HEAD_ON
 *              / |cos a|), a the angle between the ray and the voxel's
 *              normal (the hull's excess along a ray grows as 1 / cos a;
 *              a zero normal takes the most);
 *   far        the largest T over the (2 WS_HIDDEN_WINDOW + 1)^2 pixels
 *              around each pixel, the far limit of the splatting
 *              (render/splat.h): lenient at depth jumps, so a Gaussian near
 *              a contour (or near a hole) is held against the far side. A
 *              Gaussian at depth d whose centre falls in pixel (i, j) of
 *              the image is hidden when d > far(i, j) (+inf where any pixel
 *              of the window has no hull); one behind the camera or whose
 *              centre falls outside the image is not (the splatting culls
 *              or clips it anyway).
 * The tolerance and the window were chosen by measurement (docs/RESULTS.md, "Hidden
 * lines"): the visual hull stands proud of the object, most near edges seen
 * at a grazing angle and over faces seen only from above (there a tight
 * head-on tolerance keeps strokes on textured objects from sinking into
 * the body out of sight), and a tube's
 * axis lies a tube radius behind its hull's surface, while a back edge lies
 * a good part of the solid's size (tens of voxels) behind the front
 * surface. The far map is made once per view, when the view first asks
 * for it, and kept (4 bytes a pixel: 32 MB for the rose's 161 views at 224
 * px); the splatting tests each Gaussian against it as it projects it, as
 * it tests the near plane: a hidden Gaussian adds nothing to the view's
 * stroke image and gets no gradient from it. Deterministic and
 * independent of the thread count. */
#ifndef WS_HIDDEN_LINES_H
#define WS_HIDDEN_LINES_H
#include "geometry/surface.h"
#include "io/scene.h"
#include "objective/hidden_mode.h"
#include "objective/view_targets.h"
#include "nn/base/status.h"

#define WS_HIDDEN_WINDOW 2        /* px: the window is 5 x 5 */
#define WS_HIDDEN_TOLERANCE 14.0  /* voxels of the hull, the most (grazing rays) */
#define WS_HIDDEN_TOLERANCE_HEAD_ON 8.0 /* voxels, where the ray meets the hull head-on */

/* The names of ws_hidden_mode's values, as --hidden-lines takes them. */
extern const char *const ws_hidden_mode_names[2];

typedef struct ws_hidden_lines ws_hidden_lines;

/* For the views of every split of the scene (which must outlive it): hull
 * is borrowed (it must outlive it too), or NULL to carve the training
 * views' own at WS_HULL_INIT_RESOLUTION from the silhouettes of targets
 * (view_targets.h). */
int ws_hidden_lines_create(ws_hidden_lines **hl, const ws_scene *scene, const ws_scene_hull *hull,
                           ws_view_targets *targets, ws_status *st);
void ws_hidden_lines_free(ws_hidden_lines *hl);

/* *far: the far limit of view `view` of `split` (H x W, above), for
 * ws_splat_options.far; valid as long as hl. */
int ws_hidden_lines_far(ws_hidden_lines *hl, int split, int view, const float **far, ws_status *st);

#endif
