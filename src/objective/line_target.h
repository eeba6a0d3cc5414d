/* line_target.h: the line loss's target E for one view (lines.h): where a
 * line drawing of the object has its lines.
 *
 * A line drawing shows a wide part of an object by its outline and creases,
 * and a thin part (a wire, a rod, a leg: a tube a few pixels wide) by ONE
 * line along its axis, not by its two outlines, which lie a tube radius off
 * the curve on either side. So, for a photo (3 x H x W) and its optional
 * mask (1 x H x W):
 *   E0 = the photo's thin edges (render/thin_edges.h), plus the mask's
 *        outline where there is a mask (ws_thin_edges_add_outline);
 *   F  = the view's silhouette (geometry/silhouette.h: mask >= 1/2, else
 *        max_c |photo_c - background_c| > 0.02 against the border median),
 *        given: a fit makes it once and shares it (view_targets.h);
 *   D(p) = the Euclidean distance from pixel p to the nearest pixel outside
 *        F (render/distance.h; 0 outside F, INFINITY everywhere when F is
 *        the whole image);
 *   r  = WS_THIN_PART_WIDTH / 2 x max(W, H) pixels (5.6 at 224 px);
 *   O  = the opening of F by a disc of radius r: the pixels within r of a
 *        pixel with D > r (the union of the discs of radius r inside F);
 *   T  = the thin parts: the 8-connected components of F \ O of at least
 *        r^2 pixels (F \ O also holds the tips of a solid's corners, which
 *        no disc of radius r reaches: a few pixels each, not a part). A part
 *        narrower than about 2 r - 1 pixels is thin, a wider one is not;
 *   E  = E0, except: 0 at every pixel within WS_THIN_PART_MARGIN pixels of
 *        T that is in T or outside F (the thin parts' outlines and inner
 *        edges, which the detector puts on either side of the boundary);
 *        1 at every axis pixel of T: p in T such that, along at least one
 *        of the four directions (row, column, both diagonals), D(p) >=
 *        D(p + step) and D(p) > D(p - step) (D = 0 outside the image), and
 *        D(p) >= (the largest D of its 8 neighbours) - WS_THIN_AXIS_SLACK
 *        (so the short spurs that run from a bar's end towards its corners,
 *        and the pixels of a jagged outline, are no axis).
 * A photo without thin parts (every solid of `wiresketch scene`) keeps E0
 * as it is. With the hull's support (line_evidence.h; a fit has it), E is
 * then 0 also at every pixel of F farther than WS_EVIDENCE_OUTLINE_PX from
 * the background that has no support: texture inside the outline, which a
 * drawing does not draw. D and E0 do not change when the photo's contrast is scaled, so
 * neither does E. Serial, so the map does not depend on the thread count. */
#ifndef WS_LINE_TARGET_H
#define WS_LINE_TARGET_H
#include <stdint.h>
#include "io/image.h"
#include "geometry/silhouette.h"
#include "nn/base/status.h"

#define WS_THIN_PART_WIDTH 0.05 /* of the larger image side */
#define WS_THIN_PART_MARGIN 2.0 /* pixels */
#define WS_THIN_AXIS_SLACK 0.75 /* pixels */

/* edge: H x W, overwritten with E. support: NULL, or H x W (1 = the hull
 * supports a line there). mask: NULL when the view has none;
 * sil: F, made from the same photo and mask (ws_silhouette_make). Fails
 * when out of memory, or with a mask or silhouette of another size than
 * the photo. A view's target, or the user's own edge map in its place, is
 * view_targets.h's. */
int ws_line_target(const ws_image *photo, const ws_image *mask, const ws_silhouette *sil, const uint8_t *support,
                   float *edge, ws_status *st);

#endif
