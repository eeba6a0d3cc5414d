/* loss_l2.h: the pixel loss of a stroke image against its photo.
 *
 * L = mean over the H x W pixels and the 3 channels of (alpha - photo_c)^2,
 * values in [0, 1] (the stroke image is alpha on black, so it is compared
 * with the photo composited on black). A weight-free loss that needs no
 * model: the check of the splatting gradient end to end (`wiresketch grad
 * --loss l2`) and a term of the fit loss (loss.h). */
#ifndef WS_LOSS_L2_H
#define WS_LOSS_L2_H
#include <stddef.h>

/* forward: alpha (pixels), photo (3 x pixels, planar) -> L */
double ws_loss_l2_forward(const double *alpha, const float *photo, size_t pixels);

/* backward: dalpha (pixels) += weight * dL/dalpha
 * = weight * sum_c 2 (alpha - photo_c) / (3 pixels). */
void ws_loss_l2_backward(const double *alpha, const float *photo, size_t pixels, double weight,
                         double *dalpha);

#endif
