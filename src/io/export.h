/* export.h: curves as files other programs read.
 *
 * OBJ and PLY hold every curve as a polyline of WS_EXPORT_SEGMENTS straight
 * segments at uniform parameter steps (OBJ: one object `o curve_K` per
 * curve, its `v` lines and one `l` line; PLY: ascii with vertex and edge
 * elements). SVG is the sketch seen by one camera: black strokes on white,
 * one path per curve made of cubic Bezier segments (`C`), so that a vector
 * editor edits them as Beziers. The perspective image of a cubic is a
 * rational cubic, not a cubic: each segment is the cubic with the image's
 * end points and end tangents (Hermite), halved until it lies within
 * WS_EXPORT_SVG_TOLERANCE px of the image at its quarter points (most
 * curves take one segment). With a far map (hidden lines, see
 * objective/hidden_lines.h) a curve is drawn only where it is not hidden:
 * its parameter range is cut where WS_EXPORT_SVG_SAMPLES samples change
 * between seen and hidden, and each seen run is a subpath. The stroke width is
 * where the splatted stroke reaches alpha 1/2, from the Gaussian footprint
 * sigma (METHOD.md section 3) at the depth of the curve's midpoint and the spacing: about
 * 3.5 sigma with the default overlap 0.6, never below 2 sigma.
 * With a drawing (the view-dependent lines of objective/line_evidence.h,
 * the drawing a user gets) a curve is drawn only where the drawing keeps
 * curves (cut the same way), and the drawing's line pixels follow in a
 * group `hull_lines`: chains of 8-connected pixels (4-neighbours taken
 * first) as polylines through the pixel centres, 1 px wide, a lone pixel
 * as a dot. A curve with a control point at depth <= 1e-3 is left out of the SVG; when
 * all 4 are in front of the camera, so is the whole curve (it lies in their
 * convex hull). All three are written through a temporary file (outfile.h). */
#ifndef WS_EXPORT_H
#define WS_EXPORT_H
#include <stdint.h>
#include "render/camera.h"
#include "render/curves.h"
#include "nn/base/status.h"

#define WS_EXPORT_SEGMENTS 32
#define WS_EXPORT_SVG_TOLERANCE 0.05
#define WS_EXPORT_SVG_SAMPLES 128

int ws_export_obj(const char *path, const ws_curves *c, ws_status *st);
int ws_export_ply(const char *path, const ws_curves *c, ws_status *st);
/* The drawing's layers in the camera's image (H x W each): keep = 1 where
 * the curves are drawn, lines = 1 on the hull's outline and contours. */
typedef struct {
    const uint8_t *keep, *lines;
} ws_svg_drawing;

/* far: the view's far limit (H x W of the camera's image; a point at
 * depth d in pixel (i, j) is hidden when d > far[i W + j]), or NULL; drawing:
 * or NULL to draw the curves alone. */
int ws_export_svg(const char *path, const ws_curves *c, const ws_camera *cam, const float *far,
                  const ws_svg_drawing *drawing, ws_status *st);

#endif
