/* edges.h: the former weight-free loss (`--loss sobel`, METHOD.md section 6): the stroke
 * image against an edge map of the photo, at several scales.
 *
 * Edge map E of a photo (H x W, values in [0, 1]):
 *   Y = 0.299 R + 0.587 G + 0.114 B;
 *   Gx, Gy = the 3 x 3 Sobel derivatives of Y, the image extended by
 *   repeating its border pixels (so the border itself is no edge);
 *   M = sqrt(Gx^2 + Gy^2); E = min(1, M / m), where m is the mean of M over
 *   the pixels with M > max(M) / 10 (the clear edges), so a typical edge
 *   is 1, like a stroke; E = 0 for an image without any gradient.
 *
 * Loss of the stroke alpha A (H x W) against E, with S = WS_EDGES_LEVELS
 * levels and blur sigma = WS_EDGES_SIGMA pixels (of each level):
 *   D_0 = A - E;  D_s = 2 x 2 average pooling of D_{s-1} (size ceil(h/2) x
 *   ceil(w/2); a cell on an odd border averages the pixels it has);
 *   L = (1/S) sum_{s=0}^{S-1} mean over the pixels of level s of (G * D_s)^2,
 * where G * is the separable Gaussian blur (kernel exp(-t^2 / (2 sigma^2)),
 * |t| <= ceil(3 sigma), normalised to sum 1; zero outside the image).
 * Because the blur is linear, G * D_s = G * pool_s(A) - G * pool_s(E): the
 * stroke and the edges are both blurred before they are compared, so a
 * stroke a few pixels off an edge still overlaps it and gets a gradient
 * towards it (plain L2 of thin lines has almost no basin), and the coarser
 * levels widen that basin. Measured: a stroke of sigma 1.4 px beside the
 * edge of a step photo (96 x 64) sees the loss rise monotonically, and the
 * gradient point at the edge, up to 13 px away; with the pooling alone (no
 * blur) up to 5 px, beyond which the gradient's sign wanders.
 *
 * Deterministic: every pixel is computed by one thread, and the sum of
 * squares is reduced per row and then over rows in order. */
#ifndef WS_EDGES_H
#define WS_EDGES_H
#include "nn/base/status.h"

#define WS_EDGES_LEVELS 3
#define WS_EDGES_SIGMA 1.0

/* photo: 3 x H x W planar (image.h layout); edge: H x W, overwritten. The
 * map of a view's photo never changes, so callers compute it once. */
void ws_edges_target(const float *photo, int W, int H, float *edge);

/* Buffers for the pyramid of one image size. */
typedef struct ws_edges_workspace ws_edges_workspace;

int ws_edges_workspace_create(ws_edges_workspace **ws, int W, int H, ws_status *st);
void ws_edges_workspace_free(ws_edges_workspace *ws);

/* alpha, edge: H x W (the workspace's size). Returns L (NaN or Inf when
 * alpha holds one: the caller checks). */
double ws_edges_loss_forward(const double *alpha, const float *edge, int W, int H,
                             ws_edges_workspace *ws);

/* dalpha: H x W, overwritten with dL/dalpha. Needs no state of a forward
 * pass (it recomputes the pyramid, which is cheap). */
void ws_edges_loss_backward(const double *alpha, const float *edge, int W, int H,
                            ws_edges_workspace *ws, double *dalpha);

#endif
