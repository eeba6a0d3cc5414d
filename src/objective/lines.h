/* lines.h: the line-drawing loss (`--loss edges`): how well the stroke
 * image covers the photo's thin edges (thin_edges.h) and nothing else,
 * scale by scale.
 *
 * With A the stroke alpha and E the edge target (both H x W), for levels
 * s = 0 .. WS_LINES_LEVELS - 1:
 *   A_s = pool^s(A), E_s = pool^s(E)       (2 x 2 average pooling, pyramid.h)
 *   a_s = G * A_s,   e_s = G * E_s          (Gaussian blur of sigma
 *                                            WS_LINES_SIGMA px of the level)
 *   c_s = <a_s, e_s> / (sqrt(<a_s, a_s> + eps_s) sqrt(<e_s, e_s> + eps_s)),
 *         eps_s = WS_LINES_EPS x (pixels of level s),
 *   L   = sum_s w_s (1 - c_s) / sum_s w_s.
 * c_s is the cosine similarity of the two blurred images: 1 when the
 * strokes lie on the edges and cover all of them, lower for ink off the
 * edges (precision: it adds to |a_s| and nothing to <a_s, e_s>) and for
 * edges without ink (recall: <a_s, e_s> loses what |e_s| keeps), 0 for an
 * empty sketch, whose loss, 1, is the worst there is (A, E >= 0 so c_s >=
 * 0). It does not change when A is scaled, and a blurred stroke of any
 * thickness stays a ridge on its edge: the loss depends little on the
 * stroke thickness (docs/RESULTS.md: rankings at 0.005 to 0.04). eps_s keeps it
 * finite for an empty image and moves it by at most 1e-9.
 *
 * Coarse to fine: the level weights follow the fit's progress p in [0, 1]:
 *   f = (WS_LINES_LEVELS - 1) max(0, 1 - p / WS_LINES_COARSE_END),
 *   w_s = min(1, max(0, 1 + s - f)),
 * so a fit starts on the coarsest level alone (a stroke 8 px x 3 off an
 * edge still overlaps it), brings in the finer levels one after another and
 * uses all of them, equally, from p = WS_LINES_COARSE_END on, which is also
 * the loss of every evaluation (p = 1).
 *
 * Deterministic: sums run per row and then over rows in order. */
#ifndef WS_LINES_H
#define WS_LINES_H
#include "nn/base/status.h"

#define WS_LINES_LEVELS 4
#define WS_LINES_SIGMA 1.0
#define WS_LINES_EPS 1e-12
#define WS_LINES_COARSE_END 0.5

/* The level weights w_s at progress p (clamped into [0, 1]). */
void ws_lines_weights(double progress, double w[WS_LINES_LEVELS]);

typedef struct ws_lines_workspace ws_lines_workspace;

int ws_lines_workspace_create(ws_lines_workspace **ws, int W, int H, ws_status *st);
void ws_lines_workspace_free(ws_lines_workspace *ws);

/* alpha, edge: H x W (the workspace's size); w: the level weights (not all
 * 0). Returns L; with dalpha (H x W, or NULL) it is overwritten with
 * dL/dalpha. */
double ws_lines_loss(const double *alpha, const float *edge, const double w[WS_LINES_LEVELS],
                     ws_lines_workspace *ws, double *dalpha);

#endif
