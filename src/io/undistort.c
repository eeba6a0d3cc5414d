/* undistort.c: photos through a lens to and from a pinhole camera (see
 * undistort.h). */
#include <math.h>
#include "io/undistort.h"

/* Bilinear sample of channel plane `p` (w x h) at image point (u, v);
 * 0 when the point lies outside the image's [0, w] x [0, h]. */
static int sample(const float *p, int w, int h, double u, double v, float *value) {
    if (!(u >= 0 && u <= w && v >= 0 && v <= h)) return 0;
    const double a = fmin(fmax(u - 0.5, 0.0), w - 1.0), b = fmin(fmax(v - 0.5, 0.0), h - 1.0);
    int j = (int)a, i = (int)b;
    if (j > w - 2) j = w > 1 ? w - 2 : 0;
    if (i > h - 2) i = h > 1 ? h - 2 : 0;
    const double s = a - j, t = b - i;
    const int j1 = w > 1 ? j + 1 : j, i1 = h > 1 ? i + 1 : i;
    *value = (float)((1 - t) * ((1 - s) * p[(size_t)i * w + j] + s * p[(size_t)i * w + j1]) +
                     t * ((1 - s) * p[(size_t)i1 * w + j] + s * p[(size_t)i1 * w + j1]));
    return 1;
}

int ws_image_undistort(const ws_image *in, double in_scale, const ws_lens *l, const float *fill,
                       const double rect[4], int out_w, int out_h, ws_image *out, ws_status *st) {
    const double x0 = rect[0], y0 = rect[1], step_x = rect[2] / out_w, step_y = rect[3] / out_h;
    const int w = out_w, h = out_h, nc = in->channels;
    const int pinhole = ws_lens_is_pinhole(l);
    if (ws_image_alloc(out, w, h, nc, st)) return st->code;
    const size_t plane = (size_t)w * h, in_plane = (size_t)in->width * in->height;
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            const double x = (x0 + (j + 0.5) * step_x - l->cx) / l->fx,
                         y = (y0 + (i + 0.5) * step_y - l->cy) / l->fy;
            double xd, yd;
            ws_lens_distort(l, x, y, &xd, &yd);
            const int inside = pinhole || x * x + y * y <= l->r_max * l->r_max;
            for (int c = 0; c < nc; c++) {
                float value = fill[c];
                if (inside)
                    sample(in->data + c * in_plane, in->width, in->height, (l->fx * xd + l->cx) * in_scale,
                           (l->fy * yd + l->cy) * in_scale, &value);
                out->data[c * plane + (size_t)i * w + j] = value;
            }
        }
    return WS_OK;
}

int ws_image_distort(const ws_image *pinhole, const double K[4], const ws_lens *l,
                     const float *fill, ws_image *out, ws_status *st) {
    const int w = l->width, h = l->height, nc = pinhole->channels;
    if (ws_image_alloc(out, w, h, nc, st)) return st->code;
    const size_t plane = (size_t)w * h, in_plane = (size_t)pinhole->width * pinhole->height;
    for (int i = 0; i < h; i++)
        for (int j = 0; j < w; j++) {
            double x, y;
            const int ok = ws_lens_undistort(l, (j + 0.5 - l->cx) / l->fx,
                                             (i + 0.5 - l->cy) / l->fy, &x, &y) == 0;
            for (int c = 0; c < nc; c++) {
                float value = fill[c];
                if (ok)
                    sample(pinhole->data + c * in_plane, pinhole->width, pinhole->height,
                           K[0] * x + K[2], K[1] * y + K[3], &value);
                out->data[c * plane + (size_t)i * w + j] = value;
            }
        }
    return WS_OK;
}

int ws_lens_canvas(const ws_lens *l, double scale, int *width, int *height, double K[4],
                   ws_status *st) {
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    const int n = 2 * (l->width + l->height);
    for (int k = 0; k < n; k++) { /* the frame's border, every pixel */
        double u, v;
        if (k < l->width) u = k + 0.5, v = 0;
        else if (k < 2 * l->width) u = k - l->width + 0.5, v = l->height;
        else if (k < 2 * l->width + l->height) u = 0, v = k - 2 * l->width + 0.5;
        else u = l->width, v = k - 2 * l->width - l->height + 0.5;
        double x, y;
        if (ws_lens_undistort(l, (u - l->cx) / l->fx, (v - l->cy) / l->fy, &x, &y))
            return ws_fail(st, WS_EINPUT, "lens: no undistorted ray at the frame's point %g, %g", u, v);
        lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
        lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
    }
    /* the frame's own intrinsics, scaled, with the canvas' origin at the
     * border's leftmost, topmost ray less a pixel */
    K[0] = l->fx * scale;
    K[1] = l->fy * scale;
    K[2] = -lo[0] * K[0] + 1;
    K[3] = -lo[1] * K[1] + 1;
    const double cw = ceil((hi[0] - lo[0]) * K[0] + 2), ch = ceil((hi[1] - lo[1]) * K[1] + 2);
    if (!(cw <= 16384 && ch <= 16384))
        return ws_fail(st, WS_EINPUT, "lens: the frame's rays need a %g x %g pinhole canvas", cw, ch);
    *width = (int)cw;
    *height = (int)ch;
    return WS_OK;
}
