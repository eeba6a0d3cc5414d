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

/* out (lens->width x lens->height, in's channels; allocated here) is the
 * pinhole image of in (the photo through the lens, the same size): each
 * pixel centre goes through the forward model into in. Pixels whose ray
 * lies beyond the lens' one-to-one range (r_max) or outside the photo get
 * fill[c] (fill has in's channels). */
int ws_image_undistort(const ws_image *in, const ws_lens *lens, const float *fill, ws_image *out,
                       ws_status *st);

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
