/* pyramid.h: the two linear image ops of the weight-free losses (edges.h,
 * lines.h): a separable Gaussian blur and 2 x 2 average pooling, each a
 * forward/backward pair on double images (row-major, h x w); and the blur
 * with repeated borders that smooths a photo before its edges are found
 * (thin_edges.h).
 *
 * Blur: out = G * in, kernel exp(-t^2 / (2 sigma^2)) for |t| <= ceil(3 sigma),
 * normalised to sum 1, zero outside the image. Symmetric kernel and zero
 * padding make the map its own transpose: the backward pass is the forward
 * pass applied to the output gradient.
 * Pooling: out is ceil(h/2) x ceil(w/2); cell (i, j) averages the pixels
 * (2i..2i+1, 2j..2j+1) that exist (a cell on an odd border has fewer). */
#ifndef WS_PYRAMID_H
#define WS_PYRAMID_H

#define WS_BLUR_MAX_RADIUS 16

typedef struct {
    int radius;
    double k[2 * WS_BLUR_MAX_RADIUS + 1]; /* k[t + radius], t = -radius..radius */
} ws_blur_kernel;

/* sigma in (0, WS_BLUR_MAX_RADIUS / 3]; returns 0, or -1 for a sigma out of range. */
int ws_blur_kernel_init(ws_blur_kernel *g, double sigma);

/* in, out: h x w; tmp: h x w scratch; out may be in. */
void ws_blur_forward(const ws_blur_kernel *g, const double *in, double *out, double *tmp, int w, int h);

/* out = G * in with the image extended by repeating its border pixels
 * (so the border itself is no edge: render/thin_edges.h), rows first, then
 * columns. in, out, tmp: h x w; out must not be in. Not its own
 * transpose: no backward pass. */
void ws_blur_repeat_forward(const ws_blur_kernel *g, const double *in, double *out, double *tmp, int w, int h);

/* The index of the pixel a repeated border reads for x along a side of n
 * pixels: x clamped to [0, n - 1] (the blur above, the Sobel of
 * thin_edges.h). */
static inline int ws_repeat_index(int x, int n) { return x < 0 ? 0 : x >= n ? n - 1 : x; }

/* in: h x w; out: ceil(h/2) x ceil(w/2). */
void ws_pool2_forward(const double *in, int w, int h, double *out);
/* dout: ceil(h/2) x ceil(w/2); din (h x w) += the gradient through the pooling. */
void ws_pool2_backward(const double *dout, int w, int h, double *din);

#endif
