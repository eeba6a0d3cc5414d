/* silhouette_loss.h: the silhouette-consistency term (METHOD.md section 6).
 *
 * The photos prove that the object lies inside every view's silhouette, so
 * a Gaussian whose centre projects outside one pays for it. For n Gaussian
 * centres mu_g and a set of views with silhouette distance maps D_v
 * (silhouette.h: pixels from a pixel centre to the nearest object pixel
 * centre):
 *
 *     S = (1 / n) sum_g mean_v max(0, D_v(pi_v(mu_g)) - 1/2)^2
 *
 * where pi_v is view v's projection (camera.h) and D_v(x, y) the bilinear
 * interpolation of the map between pixel centres (x = u - 1/2, y = v - 1/2,
 * clamped to the map), plus the distance from (x, y) to the clamped point
 * when (x, y) lies beyond the map. The margin of half a pixel is the
 * object pixel's own extent: a centre anywhere on an object pixel pays
 * nothing. A view has no say (its part is 0) about a centre that is not in
 * front of it (depth <= 0), about a centre beyond its frame when its
 * silhouette touches the frame's edge (the object may go on there), and
 * about anything when its silhouette is empty. Distances are in pixels of
 * the working size.
 *
 * The views: of a split's V, part `part` takes views k = part mod M,
 * part mod M + M, ..., M = ceil(V / WS_SILHOUETTE_VIEWS): about 12 views
 * spread over the split, and parts 0..M-1 together take every view once.
 * The term of all V views costs more than a step's splatting and loss
 * (96 views: 8.7 ms against about 4 ms per step on the rose); a fit takes
 * the part of its batch's first view, so the views change with the batch
 * and every view has its say once per epoch.
 *
 * The term is C1 in mu wherever the bilinear map is (between pixel
 * centres); its gradient with respect to mu is exact there
 * (tests/test_silhouette_loss.c checks it against central differences).
 * Each Gaussian's value and gradient are summed on their own, in view
 * order, and the values then in Gaussian order: the bits do not depend on
 * the thread count. */
#ifndef WS_SILHOUETTE_LOSS_H
#define WS_SILHOUETTE_LOSS_H
#include "geometry/silhouette.h"
#include "io/scene.h"
#include "nn/base/status.h"

typedef struct ws_silhouette_loss ws_silhouette_loss;

/* For the views of a split of a loaded scene and their silhouettes (one per
 * view, in view order: view_targets.h's), which must outlive it. */
int ws_silhouette_loss_create(ws_silhouette_loss **out, const ws_split *split, const ws_silhouette *sil,
                              ws_status *st);
void ws_silhouette_loss_free(ws_silhouette_loss *s);

#define WS_SILHOUETTE_VIEWS 12

/* M for a split of nviews views (above). */
int ws_silhouette_loss_stride(int nviews);

/* *value = S for the n centres mu (n x 3) over the views of part `part`
 * (>= 0; above); 0 for n = 0. It also keeps dS/dmu for the backward. */
int ws_silhouette_loss_forward(ws_silhouette_loss *s, const double *mu, int n, int part, double *value,
                               ws_status *st);
/* dmu (n x 3 of the last forward, overwritten) = scale x dS/dmu there. */
void ws_silhouette_loss_backward(const ws_silhouette_loss *s, double scale, double *dmu);

#endif
