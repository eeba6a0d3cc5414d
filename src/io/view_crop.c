/* view_crop.c: the working view's crop (see view_crop.h). */
#include <math.h>
#include "io/view_crop.h"

/* The start of a crop of `length` pixels of a frame of `size` whose middle
 * is as near `at` as the frame allows. */
static int place(double at, int length, int size) {
    const long x0 = lround(at - 0.5 * length);
    return (int)(x0 < 0 ? 0 : x0 > size - length ? size - length : x0);
}

/* The image point of world point p in the frame (square pixels of focal fx
 * across and fy down); 0 when p is not in front of the camera. */
static int project(const ws_camera *frame, double fx, double fy, double cx, double cy, const double p[3],
                   double *u, double *v) {
    double c[3];
    ws_camera_to_cam(frame, p, c);
    if (!(-c[2] > 0)) return 0;
    *u = cx + fx * c[0] / -c[2];
    *v = cy - fy * c[1] / -c[2];
    return 1;
}

/* The box's projected extent [u0, u1] x [v0, v1]; 0 when a corner is not in
 * front of the camera (its projection is then unbounded). */
static int box_extent(const ws_camera *frame, double fx, double fy, double cx, double cy, const double box[6],
                      double ext[4]) {
    ext[0] = ext[2] = INFINITY;
    ext[1] = ext[3] = -INFINITY;
    for (int corner = 0; corner < 8; corner++) {
        const double p[3] = {box[(corner & 1) ? 3 : 0], box[(corner & 2) ? 4 : 1], box[(corner & 4) ? 5 : 2]};
        double u, v;
        if (!project(frame, fx, fy, cx, cy, p, &u, &v)) return 0;
        ext[0] = fmin(ext[0], u), ext[1] = fmax(ext[1], u);
        ext[2] = fmin(ext[2], v), ext[3] = fmax(ext[3], v);
    }
    return 1;
}

int ws_view_crop(double fx, double fy, double cx, double cy, int w, int h, const double c2w[4][4],
                 const double target[3], const double box[6], int W, int H, const char *what, int crop[4],
                 ws_camera *cam, ws_status *st) {
    const double aspect = fx / fy * W / H; /* cw / ch wanted */
    int cw, ch;
    if ((double)w / h >= aspect) {
        ch = h;
        cw = (int)fmin(w, fmax(1, lround(h * aspect)));
    } else {
        cw = w;
        ch = (int)fmin(h, fmax(1, lround(w / aspect)));
    }
    ws_camera frame;
    if (ws_camera_init_pinhole(&frame, c2w, fx, cx, cy, w, h, what, st)) return st->code;
    double u = 0.5 * w, v = 0.5 * h, ext[4];
    if (box && box_extent(&frame, fx, fy, cx, cy, box, ext)) {
        const double grow = 1 + 2 * WS_VIEW_CROP_MARGIN;
        /* the share of the largest crop the box needs, at least W x H pixels */
        const double zoom = fmin(1, fmax(fmax((ext[1] - ext[0]) * grow / cw, (ext[3] - ext[2]) * grow / ch),
                                         fmax((double)W / cw, (double)H / ch)));
        ch = (int)fmin(ch, fmax(1, lround(ch * zoom)));
        cw = (int)fmin(cw, fmax(1, lround(ch * aspect)));
        u = 0.5 * (ext[0] + ext[1]);
        v = 0.5 * (ext[2] + ext[3]);
    } else if (target) {
        project(&frame, fx, fy, cx, cy, target, &u, &v);
    }
    const int x0 = place(u, cw, w), y0 = place(v, ch, h);
    const double sx = (double)W / cw, sy = (double)H / ch;
    crop[0] = x0;
    crop[1] = y0;
    crop[2] = cw;
    crop[3] = ch;
    return ws_camera_init_pinhole(cam, c2w, sqrt(fx * sx * fy * sy), (cx - x0) * sx, (cy - y0) * sy, W, H, what,
                                  st);
}
