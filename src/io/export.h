/* export.h: curves as files other programs read.
 *
 * OBJ and PLY hold every curve as a polyline of WS_EXPORT_SEGMENTS straight
 * segments at uniform parameter steps (OBJ: `v` and `l` lines; PLY: ascii
 * with vertex and edge elements). SVG is the sketch seen by one camera:
 * black strokes on white, each curve a polyline path of its projection
 * (the perspective image of a Bezier is not a Bezier). The stroke width is
 * where the splatted stroke reaches alpha 1/2, from the Gaussian footprint
 * sigma (METHOD.md section 3) at the depth of the curve's midpoint and the spacing: about
 * 3.5 sigma with the default overlap 0.6, never below 2 sigma.
 * A curve with a control point at depth <= 1e-3 is left out of the SVG; when
 * all 4 are in front of the camera, so is the whole curve (it lies in their
 * convex hull). All three are written through a temporary file (outfile.h). */
#ifndef WS_EXPORT_H
#define WS_EXPORT_H
#include "render/camera.h"
#include "render/curves.h"
#include "nn/base/status.h"

#define WS_EXPORT_SEGMENTS 32

int ws_export_obj(const char *path, const ws_curves *c, ws_status *st);
int ws_export_ply(const char *path, const ws_curves *c, ws_status *st);
int ws_export_svg(const char *path, const ws_curves *c, const ws_camera *cam, ws_status *st);

#endif
