/* undistort.h: photos through a lens to and from a pinhole camera
 * (METHOD.md, "Lens models").
 *
 * A photo taken through a lens (render/lens.h) is resampled once, on load,
 * to the pinhole camera of the same focal lengths, principal point and
 * size, so that everything downstream keeps its pinhole code; the test bed
 * goes the other way, from a pinhole render to a photo through the lens.
 * Both sample bilinearly, pixel centres at integer + 1/2. */
#ifndef WS_UNDISTORT_H
#define WS_UNDISTORT_H
#include "io/image.h"
#include "render/lens.h"
#include "nn/base/status.h"

/* out (out_w x out_h pixels, in's channels; allocated here) is the part
 * rect = {x0, y0, w, h} (the lens' frame's pixels, from its corner: w x h
 * pixels from column x0, row y0) of the pinhole image of the photo
 * through the lens: out's
 * pixel centre (j + 1/2, i + 1/2) is the frame's (x0 + (j + 1/2) w / out_w,
 * y0 + (i + 1/2) h / out_h), which goes through the forward model into
 * in. in: that photo at in_scale of the frame's size (1: the frame's own;
 * 1/4: decoded at a quarter a side, image.h). Pixels whose ray lies beyond
 * the lens' one-to-one range (r_max; a pinhole has none) or outside the
 * photo get fill[c] (fill has in's channels). A part at the frame's own
 * scale is the same pixels as the whole image cropped, made without the
 * rest (a capture's working crop is a small part of a phone photo). */
int ws_image_undistort(const ws_image *in, double in_scale, const ws_lens *lens, const float *fill,
                       const double rect[4], int out_w, int out_h, ws_image *out, ws_status *st);

/* out (lens->width x lens->height) is the photo through the lens of the
 * scene that `pinhole` shows through a pinhole camera of intrinsics
 * K = {fx, fy, cx, cy} (the same camera's pose): each pixel centre goes
 * through the inverse model (lens.h) into `pinhole`; fill where that lands
 * outside it. */
int ws_image_distort(const ws_image *pinhole, const double K[4], const ws_lens *lens,
                     const float *fill, ws_image *out, ws_status *st);

/* The pinhole canvas that ws_image_distort needs for the whole frame at
 * `scale` pixels per lens pixel: its size and K, from the inverse of the
 * frame's border (plus a pixel of margin). Fails when the lens has no
 * inverse at the border. */
int ws_lens_canvas(const ws_lens *lens, double scale, int *width, int *height, double K[4],
                   ws_status *st);

#endif
