/* loss_l2.c: the pixel loss (see loss_l2.h). */
#include "objective/loss_l2.h"

double ws_loss_l2_forward(const double *alpha, const float *photo, size_t pixels) {
    double sum = 0;
    for (int c = 0; c < 3; c++)
        for (size_t p = 0; p < pixels; p++) {
            double diff = alpha[p] - photo[c * pixels + p];
            sum += diff * diff;
        }
    return sum / (3.0 * pixels);
}

void ws_loss_l2_backward(const double *alpha, const float *photo, size_t pixels, double weight,
                         double *dalpha) {
    double scale = weight * 2.0 / (3.0 * pixels);
    for (size_t p = 0; p < pixels; p++) {
        double d = 3.0 * alpha[p] - photo[p] - photo[pixels + p] - photo[2 * pixels + p];
        dalpha[p] += scale * d;
    }
}
