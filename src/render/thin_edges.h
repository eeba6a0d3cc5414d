/* thin_edges.h: the edge target of the line loss (lines.h): edges one pixel
 * wide wherever the photo changes, whatever the contrast (Canny's detector
 * with thresholds taken from the image's own statistics).
 *
 * For a photo (3 x H x W planar, values in [0, 1]):
 *   Y = 0.299 R + 0.587 G + 0.114 B;
 *   S = Y smoothed by a Gaussian of sigma WS_THIN_SIGMA pixels, |t| <=
 *       ceil(3 sigma), the image extended by repeating its border pixels
 *       (so the border itself is no edge);
 *   Gx, Gy = the 3 x 3 Sobel derivatives of S divided by 8 (borders
 *       repeated), M = sqrt(Gx^2 + Gy^2);
 *   non-maximum suppression: pixel p is a ridge pixel when M(p) > 0 and,
 *       with q+ and q- its two 8-neighbours along the gradient direction
 *       rounded to a multiple of 45 degrees, M(p) >= M(q+) and M(p) > M(q-);
 *   thresholds: m = the largest M; the candidates are the ridge pixels with
 *       M > WS_THIN_FLOOR m; high = the WS_THIN_HIGH quantile (nearest rank)
 *       of their M, low = WS_THIN_LOW high;
 *   hysteresis: the edge pixels are the ridge pixels with M >= low that are
 *       8-connected through such pixels to one with M >= high;
 *   E = 1 on edge pixels, 0 elsewhere (all 0 for an image without gradient).
 * Thresholds relative to the image's own ridge strengths make the map the
 * same when the contrast of the whole photo is scaled, and a quantile (not
 * a fraction of the maximum) keeps weak creases between similarly lit faces
 * beside a strong silhouette. */
#ifndef WS_THIN_EDGES_H
#define WS_THIN_EDGES_H
#include "nn/base/status.h"

#define WS_THIN_SIGMA 1.0
#define WS_THIN_FLOOR 0.01
#define WS_THIN_HIGH 0.1
#define WS_THIN_LOW 0.4

/* edge: H x W, overwritten with E. Fails only when out of memory. */
int ws_thin_edges(const float *photo, int W, int H, float *edge, ws_status *st);

/* The silhouette's outline where the view has a mask (an alpha channel or a
 * mask_path image; scene.h): edge = 1 also on every object pixel (mask >=
 * 1/2) with a 4-neighbour inside the image that is background. Photos
 * composited onto a background of the object's own brightness lose their
 * outline; the mask keeps it. */
void ws_thin_edges_add_outline(const float *mask, int W, int H, float *edge);

#endif
