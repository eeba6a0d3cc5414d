/* turntable.h: sketch renders for people to look at, and the fly-around.
 *
 * A sketch render is the stroke image of METHOD.md section 3 drawn the way
 * sketches are drawn: black strokes on white, gray = 255 * (1 - alpha),
 * splatted with the default options (cut-off 4 sigma).
 *
 * The fly-around ("turntable") is a semi-helical camera path like the
 * original CLIPasso-3D's, made to loop: frame i of n sits at azimuth
 * -90 + 360 i / n degrees (frame 0 looks at the scene from -y, Blender's
 * front view) and elevation -10 + 25 (1 - cos(2 pi i / n)) degrees, which
 * climbs from -10 to +40 at half-turn and comes back down, at a constant
 * distance from the scene centre, looking at the centre with the world's +z
 * (Blender's up) pointing up in the image. */
#ifndef WS_TURNTABLE_H
#define WS_TURNTABLE_H
#include "render/camera.h"
#include "render/curves.h"
#include "io/scene.h"
#include "render/splat.h"
#include "nn/base/status.h"

/* Everything a sketch render needs, allocated once for one image size. */
typedef struct {
    int width, height;
    ws_splat *splat;
    ws_gaussians g;
    double *alpha;       /* height x width */
    unsigned char *gray; /* height x width: the render, 255 * (1 - alpha) */
} ws_sketch_renderer;

int ws_sketch_renderer_init(ws_sketch_renderer *r, int width, int height, ws_status *st);
void ws_sketch_renderer_free(ws_sketch_renderer *r);

/* Renders the curves seen by `cam` (of the renderer's size) into r->gray. */
int ws_sketch_render(ws_sketch_renderer *r, const ws_curves *c, const ws_camera *cam,
                     ws_status *st);

/* Turns the sketch's render of a view (curves, H x W grey) into the
 * drawing a user gets of it (drawing, H x W grey; may be curves itself):
 * objective/line_evidence.h's, which the turntable, the test renders and
 * the drawing score (metrics/drawing_score.h) all show. */
typedef int (*ws_drawing_render_fn)(void *ctx, const ws_camera *cam, const unsigned char *curves,
                                    unsigned char *drawing, ws_status *st);

/* The turntable distance: the mean distance of the split's cameras from
 * `center` (0 for an empty split). */
double ws_turntable_distance(const ws_split *split, const double center[3]);

/* Camera of frame i of an n-frame turntable, size x size pixels. */
int ws_turntable_camera(ws_camera *cam, const double center[3], double distance,
                        double camera_angle_x, int size, int i, int nframes, ws_status *st);

/* Renders the n-frame turntable of the curves into a looping gray GIF at
 * PATH, each frame turned into the drawing by render(ctx, ...) unless
 * render is NULL; one turn takes about 6 s (the original's rotation time),
 * each frame at least 2/100 s. */
int ws_turntable_gif(const char *path, const ws_curves *c, const double center[3],
                     double distance, double camera_angle_x, int size, int nframes,
                     ws_drawing_render_fn render, void *ctx, ws_status *st);

#endif
