/* image.h: float images, PNG and JPEG input and output.
 *
 * A ws_image is planar (channel-major): pixel (row i, column j) of channel c
 * is data[(c * height + i) * width + j], values in [0, 1]. Photos are always
 * 3 channels (RGB); stroke images are 1 channel (alpha). */
#ifndef WS_IMAGE_H
#define WS_IMAGE_H
#include "nn/base/status.h"

typedef struct {
    int width, height, channels;
    float *data;
} ws_image;

int ws_image_alloc(ws_image *img, int width, int height, int channels, ws_status *st);
void ws_image_free(ws_image *img);

/* Reads a PNG or a JPEG, told apart by the file's first bytes (never by
 * its name). PNG: 8- or 16-bit; gray, gray+alpha, RGB, RGBA or palette.
 * JPEG: see jpeg.h. Alpha is composited onto `background` (RGB in [0,1]);
 * the result is 3 channels, resampled to width x height when the file has
 * another size (width = 0 keeps the file's size). Both formats have the
 * same size limit. Every failure names the file: "PATH: not a PNG or JPEG
 * file" ("PATH: a HEIC image, not PNG or JPEG (convert it to JPEG or
 * PNG)" for the formats a photo often comes in otherwise: GIF, HEIC, HEIF,
 * AVIF, WebP, TIFF, BMP, OpenEXR, JPEG 2000), "PATH: truncated or corrupt
 * PNG (...)", "PATH: truncated or corrupt JPEG (...)", "PATH: cannot
 * open: ...". */
int ws_image_read(const char *path, int width, int height, const float background[3],
                  ws_image *out, ws_status *st);

/* ws_image_read, and the file's alpha channel (values in [0, 1]) into
 * `alpha` (1 channel, resampled like the colours), whose data is NULL when
 * the file has no alpha channel (every JPEG) or every pixel is opaque. */
int ws_image_read_alpha(const char *path, int width, int height, const float background[3],
                        ws_image *out, ws_image *alpha, ws_status *st);

/* ws_image_read_alpha at the file's own size, or at 1 / reduce (2, 4 or 8)
 * of it a side, ceil(W / reduce) x ceil(H / reduce): a JPEG through
 * libjpeg's scaled decoding, a PNG as the mean of each block of reduce x
 * reduce pixels (colours composited first, alpha averaged alike), its
 * rows read one at a time unless it is interlaced; *reduced: the factor
 * it was decoded at, file_size: the file's own W and H. A phone photo of
 * 4032 x 3024 read for a working view of 224 px needs a small part of its
 * pixels. */
int ws_image_read_reduced(const char *path, int reduce, const float background[3], ws_image *out,
                          ws_image *alpha, int *reduced, int file_size[2], ws_status *st);

/* Writes a 1- or 3-channel image as an 8-bit gray or RGB PNG, each value
 * round(255 * clamp(v, 0, 1)), through a temporary file (outfile.h). */
int ws_png_write(const char *path, const ws_image *img, ws_status *st);

/* The same as a baseline JPEG of `quality` (1-100; 4:4:4, see jpeg.h). */
int ws_image_write_jpeg(const char *path, const ws_image *img, int quality, ws_status *st);

/* The rectangle of columns [x0, x0 + width) and rows [y0, y0 + height) of
 * `in` (which must contain it) into `out` (allocated here). */
int ws_image_crop(const ws_image *in, int x0, int y0, int width, int height, ws_image *out,
                  ws_status *st);

/* The median of each of the first three channels over the image's border
 * pixels (its outermost rows and columns, each pixel once): the background
 * colour of a photo of an object in the middle. scratch: 2 (width + height)
 * floats. */
void ws_image_border_median(const ws_image *img, float out[3], float *scratch);

/* Resamples `in` to width x height into `out` (allocated here): area
 * averaging when shrinking, bilinear when enlarging, per axis. */
int ws_image_resample(const ws_image *in, int width, int height, ws_image *out, ws_status *st);

#endif
