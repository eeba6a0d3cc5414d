/* view_crop.c: the working view's crop (see view_crop.h). */
#include <math.h>
#include "io/view_crop.h"

/* The start of a crop of `length` pixels of a frame of `size` whose middle
 * is as near `at` as the frame allows. */
static int place(double at, int length, int size) {
    const long x0 = lround(at - 0.5 * length);
    return (int)(x0 < 0 ? 0 : x0 > size - length ? size - length : x0);
}

int ws_view_crop(double fx, double fy, double cx, double cy, int w, int h, const double c2w[4][4],
                 const double target[3], int W, int H, const char *what, int crop[4], ws_camera *cam,
                 ws_status *st) {
    const double aspect = fx / fy * W / H; /* cw / ch wanted */
    int cw, ch;
    if ((double)w / h >= aspect) {
        ch = h;
        cw = (int)fmin(w, fmax(1, lround(h * aspect)));
    } else {
        cw = w;
        ch = (int)fmin(h, fmax(1, lround(w / aspect)));
    }
    /* The target's image point in the frame: the whole-frame camera of
     * these intrinsics (square pixels of focal fx across and fy down). */
    double u = 0.5 * w, s = 0.5 * h;
    ws_camera frame;
    if (ws_camera_init_pinhole(&frame, c2w, fx, cx, cy, w, h, what, st)) return st->code;
    double c[3];
    if (target) ws_camera_to_cam(&frame, target, c);
    if (target && -c[2] > 0) {
        u = cx + fx * c[0] / -c[2];
        s = cy - fy * c[1] / -c[2];
    }
    const int x0 = place(u, cw, w), y0 = place(s, ch, h);
    const double sx = (double)W / cw, sy = (double)H / ch;
    crop[0] = x0;
    crop[1] = y0;
    crop[2] = cw;
    crop[3] = ch;
    return ws_camera_init_pinhole(cam, c2w, sqrt(fx * sx * fy * sy), (cx - x0) * sx, (cy - y0) * sy, W, H, what,
                                  st);
}
