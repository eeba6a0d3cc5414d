/* splat.h: the differentiable Gaussian splatting rasteriser (METHOD.md section 3).
 *
 * For each Gaussian (centre mu, world radius r) seen by a camera at depth
 * d > near (and, with a far limit, d <= far(i, j) of the pixel (i, j) its
 * centre falls in): image point (u, v), footprint sigma = f r / d, weight
 * w = exp(-((j + 1/2 - u)^2 + (i + 1/2 - v)^2) / (2 sigma^2)) at pixel
 * (row i, col j), whose centre is (j + 1/2, i + 1/2) (camera.h),
 * cut off beyond `cutoff` sigmas (INFINITY = the exact sum over all pixels);
 * alpha = 1 - prod_k (1 - w_k). The backward pass gives dL/dmu from dL/dalpha
 * and stays finite at w = 1, for sigma far below a pixel or far above the
 * image, and for thousands of Gaussians on one pixel. Deterministic for a
 * given input and thread count. */
#ifndef WS_SPLAT_H
#define WS_SPLAT_H
#include "render/camera.h"
#include "nn/base/status.h"

typedef struct {
    double cutoff; /* in sigmas; INFINITY = exact; default 4 */
    double near;   /* Gaussians with depth <= near are culled; default 1e-3 */
    const float *far; /* NULL, or a per-pixel far limit (height x width): a Gaussian at
                       * depth d whose centre falls in pixel (i, j) of the image is culled
                       * too when d > far[i width + j]; one whose centre falls outside the
                       * image is not (hidden-line removal, objective/hidden_lines.h);
                       * default NULL */
} ws_splat_options;

void ws_splat_options_default(ws_splat_options *opt);

/* A workspace for one image size; it keeps what the last forward pass needs
 * for its backward pass, so use one workspace per image in flight. */
typedef struct ws_splat ws_splat;

int ws_splat_create(ws_splat **s, int width, int height, ws_status *st);
void ws_splat_free(ws_splat *s);

/* alpha: height x width, overwritten. mu: n x 3 world centres. */
int ws_splat_forward(ws_splat *s, const ws_camera *cam, const double *mu, int n, double radius,
                     const ws_splat_options *opt, double *alpha, ws_status *st);

/* dalpha: height x width; dmu: n x 3, overwritten (culled Gaussians get 0).
 * Uses the camera, centres and options of the last forward pass. */
int ws_splat_backward(ws_splat *s, const double *dalpha, double *dmu, ws_status *st);

#endif
