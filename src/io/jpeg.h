/* jpeg.h: JPEG input/output through libjpeg-turbo (image.h reads either
 * format, chosen by the file's first bytes).
 *
 * Baseline and progressive JPEGs, gray or YCbCr/RGB, 8 bits per sample, are
 * decoded; CMYK (Adobe) files are refused, as is any file libjpeg finds
 * truncated or corrupt (its warnings included: a cut-off file otherwise
 * decodes to grey rows without a word). */
#ifndef WS_JPEG_H
#define WS_JPEG_H
#include <stdint.h>
#include <stdio.h>
#include "nn/base/status.h"

/* Decodes the JPEG open as fp (positioned at its start) into *pixels
 * (allocated here; rows of width * channels bytes, channels 1 for gray
 * and 3 for RGB), refusing more than max_side on a side or max_pixels in
 * all (of the file's own size) before anything that size is allocated.
 * reduce (1, 2, 4 or 8): the image 1 / reduce the file's size a side,
 * ceil(W / reduce) x ceil(H / reduce), as libjpeg decodes it at that scale;
 * file_size: the file's own W and H.
 * Messages: "PATH: truncated or corrupt JPEG (libjpeg's reason)", "PATH:
 * CMYK JPEG is not supported (convert it to RGB)", "PATH: image too large
 * (W x H pixels)". */
int ws_jpeg_decode(FILE *fp, const char *path, int max_side, uint64_t max_pixels, int reduce,
                   unsigned char **pixels, int *width, int *height, int *channels, int file_size[2],
                   ws_status *st);

/* Writes width x height pixels of `channels` (1: gray, 3: RGB) interleaved
 * bytes as a baseline JPEG of `quality` (1-100, 4:4:4 chroma: the test
 * bed's photos keep their colour edges), through a temporary file
 * (outfile.h). */
int ws_jpeg_encode(const char *path, const unsigned char *pixels, int width, int height,
                   int channels, int quality, ws_status *st);

#endif
