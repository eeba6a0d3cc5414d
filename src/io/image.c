/* image.c: float images, PNG input/output through libpng (JPEG: jpeg.c), resampling
 * (see image.h).
 *
 * libpng reports errors by calling an error function that must not return.
 * Ours records libpng's reason and longjmps back into the one small "stage"
 * function that made the libpng call; each stage has its own setjmp and
 * modifies no local variable after it, so nothing is indeterminate after the
 * jump, and all allocation happens outside the stages. A corrupt file thus
 * becomes "PATH: truncated or corrupt PNG (libpng's reason)", never a crash. */
#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "io/image.h"
#include "io/jpeg.h"
#include "base/limits.h"
#include "base/outfile.h"
#include "nn/base/fileopen.h"

/* The largest image (PNG or JPEG) we agree to decode, checked right after
 * the header is read and before anything the size of the image is
 * allocated: at most 8 bytes per pixel (16-bit RGBA), so 512 MB of decoded
 * samples. */
#define MAX_PNG_SIDE 32768
#define MAX_PNG_PIXELS (64u * 1024u * 1024u)
/* The largest image file opened: the largest image's samples, uncompressed. */
#define MAX_PNG_FILE_BYTES ((uint64_t)MAX_PNG_PIXELS * 8)

int ws_image_alloc(ws_image *img, int width, int height, int channels, ws_status *st) {
    img->data = NULL;
    img->width = img->height = img->channels = 0;
    if (width <= 0 || height <= 0 || channels <= 0)
        return ws_fail(st, WS_EINTERNAL, "image size %d x %d x %d is not positive", width, height,
                       channels);
    img->data = ws_malloc((size_t)width * height * channels * sizeof(float), "an image", st);
    if (!img->data) return st->code;
    img->width = width;
    img->height = height;
    img->channels = channels;
    return WS_OK;
}

void ws_image_free(ws_image *img) {
    free(img->data);
    img->data = NULL;
    img->width = img->height = img->channels = 0;
}

/* ---------------------------------------------------------------- libpng glue */

typedef struct {
    FILE *fp;
    char reason[256]; /* libpng's last error message */
} png_io;

static void on_png_error(png_structp png, png_const_charp msg) {
    png_io *io = png_get_error_ptr(png);
    snprintf(io->reason, sizeof io->reason, "%s", msg);
    png_longjmp(png, 1);
}

/* Warnings (bad ancillary chunks, gamma oddities) do not stop a decode. */
static void on_png_warning(png_structp png, png_const_charp msg) {}

/* Our own read function, so that a short file says so instead of libpng's
 * generic "Read Error". */
static void on_png_read(png_structp png, png_bytep data, size_t length) {
    png_io *io = png_get_io_ptr(png);
    if (fread(data, 1, length, io->fp) == length) return;
    if (ferror(io->fp)) png_error(png, strerror(errno ? errno : EIO));
    png_error(png, "unexpected end of file");
}

/* Stage 1: the chunks up to the image data. */
static int read_info_stage(png_structp png, png_infop info) {
    if (setjmp(png_jmpbuf(png))) return -1;
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    return 0;
}

/* Stage 2: the transformations that give 8- or 16-bit gray, gray+alpha, RGB
 * or RGBA samples (palette expanded, low bit depths widened to 8, a tRNS
 * chunk made an alpha channel). */
static int transform_stage(png_structp png, png_infop info) {
    if (setjmp(png_jmpbuf(png))) return -1;
    png_set_expand(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    return 0;
}

/* Stage 3 of an interlaced file: every row (its passes combined), then the
 * chunks after the image (so that a file cut off after its pixel data is
 * reported too). */
static int read_pixels_stage(png_structp png, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) return -1;
    png_read_image(png, rows);
    png_read_end(png, NULL);
    return 0;
}

/* Stage 3 of a file that is not interlaced, one row at a time: the next
 * row, ... */
static int read_row_stage(png_structp png, png_bytep row) {
    if (setjmp(png_jmpbuf(png))) return -1;
    png_read_row(png, row, NULL);
    return 0;
}

/* ... and after the last, the chunks after the image. */
static int read_end_stage(png_structp png) {
    if (setjmp(png_jmpbuf(png))) return -1;
    png_read_end(png, NULL);
    return 0;
}

/* Adds one row of decoded samples (`channels` of 8 or 16 bits, interleaved)
 * to the sums of its block row: sum[4 k + c] gathers colour c of the file's
 * columns [k reduce, (k + 1) reduce), gray copied to R, G and B and alpha a
 * composited, a c + (1 - a) bg on the stored values (no gamma), and
 * sum[4 k + 3] gathers a. */
static void add_samples(const png_byte *row, int width, int channels, int depth, const float background[3],
                        int reduce, double *sum) {
    const double scale = depth == 16 ? 1.0 / 65535.0 : 1.0 / 255.0;
    const int has_alpha = channels == 2 || channels == 4, colour = channels >= 3;
    for (int j = 0; j < width; j++) {
        double v[4];
        for (int c = 0; c < channels; c++) {
            const png_byte *s = row + ((size_t)j * channels + c) * (depth / 8);
            v[c] = (depth == 16 ? (s[0] << 8 | s[1]) : s[0]) * scale;
        }
        const double a = has_alpha ? v[channels - 1] : 1.0;
        double *block = sum + 4 * (j / reduce);
        for (int c = 0; c < 3; c++) block[c] += a * v[colour ? c : 0] + (1.0 - a) * background[c];
        block[3] += a;
    }
}

/* Row i of out (and of alpha, when given) from its block row's sums over
 * `rows` of the file's rows, which are then cleared: each block's mean
 * over the file's pixels it holds (the last column of blocks and the last
 * block row may hold fewer). */
static void store_block_row(double *sum, int file_width, int reduce, int rows, int i, ws_image *out, float *alpha) {
    const size_t plane = (size_t)out->width * out->height, at = (size_t)i * out->width;
    for (int k = 0; k < out->width; k++) {
        const int cols = file_width - k * reduce < reduce ? file_width - k * reduce : reduce;
        const double n = (double)cols * rows;
        for (int c = 0; c < 3; c++) out->data[c * plane + at + k] = (float)(sum[4 * k + c] / n);
        if (alpha) alpha[at + k] = (float)(sum[4 * k + 3] / n);
    }
    memset(sum, 0, sizeof *sum * 4 * out->width);
}

/* Decodes an open file whose 8 signature bytes were consumed into a
 * 3-channel image at 1 / reduce of the file's size a side, each pixel the
 * mean of the block of reduce x reduce file pixels it covers (reduce 1:
 * the file's own pixels), and (when `alpha` is given) its alpha channel
 * the same way, left empty when the file has none or it is 1 everywhere.
 * A file that is not interlaced is read one row at a time, so only the
 * reduced image is held; an interlaced one is held whole. file_size: the
 * file's own width and height. */
static int decode_png(FILE *fp, const char *path, int reduce, const float background[3], ws_image *out,
                      ws_image *alpha, int file_size[2], ws_status *st) {
    png_io io = {fp, ""};
    png_structp png =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &io, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    png_bytep pixels = NULL;
    png_bytepp rows = NULL;
    double *sum = NULL;
    int rc = WS_OK;
    if (!info) {
        rc = ws_fail(st, WS_ENOMEM, "%s: out of memory creating a PNG decoder", path);
        goto done;
    }
    png_set_read_fn(png, &io, on_png_read);
    if (read_info_stage(png, info)) {
        rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt PNG (%s)", path, io.reason);
        goto done;
    }
    const uint32_t file_w = png_get_image_width(png, info),
                   file_h = png_get_image_height(png, info);
    if (file_w > MAX_PNG_SIDE || file_h > MAX_PNG_SIDE ||
        (uint64_t)file_w * file_h > MAX_PNG_PIXELS) {
        rc = ws_fail(st, WS_EINPUT, "%s: image too large (%u x %u pixels)", path, file_w, file_h);
        goto done;
    }
    const int width = (int)file_w, height = (int)file_h;
    file_size[0] = width;
    file_size[1] = height;
    const int interlaced = png_get_interlace_type(png, info) != PNG_INTERLACE_NONE;
    if (transform_stage(png, info)) {
        rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt PNG (%s)", path, io.reason);
        goto done;
    }
    const int channels = png_get_channels(png, info), depth = png_get_bit_depth(png, info);
    if (channels < 1 || channels > 4 || (depth != 8 && depth != 16)) {
        rc = ws_fail(st, WS_EINPUT, "%s: unsupported PNG layout (%d channels of %d bits)", path,
                     channels, depth);
        goto done;
    }
    const int has_alpha = channels == 2 || channels == 4;
    const int out_w = (width + reduce - 1) / reduce, out_h = (height + reduce - 1) / reduce;
    const size_t rowbytes = png_get_rowbytes(png, info);
    /* per block row: the float planes (3, and alpha), and an interlaced
     * file's samples; checked before either is allocated (base/limits.h) */
    char what[WS_PATH_MAX + 100];
    snprintf(what, sizeof what, "%s (%d x %d pixels, %d channels of %d bits, decoded)", path, width, height,
             channels, depth);
    size_t bytes, need[2] = {(size_t)out_w * sizeof(float) * (3 + has_alpha) + (interlaced ? rowbytes * reduce : 0),
                             (size_t)out_h};
    if ((rc = ws_size_product(what, need, 2, WS_MAX_DECODE_BYTES, "a decoded image", &bytes, st))) goto done;
    pixels = ws_malloc(rowbytes * (interlaced ? height : 1), path, st);
    rows = pixels ? ws_malloc(sizeof *rows * (interlaced ? height : 1), path, st) : NULL;
    sum = rows ? ws_calloc(4 * (size_t)out_w, sizeof *sum, path, st) : NULL;
    if (!sum || (rc = ws_image_alloc(out, out_w, out_h, 3, st)) ||
        (alpha && has_alpha && (rc = ws_image_alloc(alpha, out_w, out_h, 1, st)))) {
        rc = st->code;
        goto done;
    }
    for (int i = 0; i < (interlaced ? height : 1); i++) rows[i] = pixels + rowbytes * i;
    if (interlaced && read_pixels_stage(png, rows)) {
        rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt PNG (%s)", path, io.reason);
        goto done;
    }
    for (int i = 0; i < height; i++) {
        if (!interlaced && read_row_stage(png, rows[0])) {
            rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt PNG (%s)", path, io.reason);
            goto done;
        }
        add_samples(rows[interlaced ? i : 0], width, channels, depth, background, reduce, sum);
        if ((i + 1) % reduce == 0 || i + 1 == height)
            store_block_row(sum, width, reduce, i % reduce + 1, i / reduce, out, alpha ? alpha->data : NULL);
    }
    if (!interlaced && read_end_stage(png)) {
        rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt PNG (%s)", path, io.reason);
        goto done;
    }
    if (alpha && alpha->data) {
        size_t k = 0, n = (size_t)out_w * out_h;
        while (k < n && alpha->data[k] == 1.0f) k++;
        if (k == n) ws_image_free(alpha); /* opaque: no information */
    }
done:
    png_destroy_read_struct(png ? &png : NULL, info ? &info : NULL, NULL);
    free(sum);
    free(rows);
    free(pixels);
    return rc;
}

/* A JPEG (jpeg.c) as a 3-channel image; gray is copied to R, G and B. */
static int decode_jpeg(FILE *fp, const char *path, int reduce, ws_image *out, int file_size[2], ws_status *st) {
    unsigned char *pixels;
    int w, h, nc;
    if (ws_jpeg_decode(fp, path, MAX_PNG_SIDE, MAX_PNG_PIXELS, reduce, &pixels, &w, &h, &nc, file_size, st))
        return st->code;
    int rc = ws_image_alloc(out, w, h, 3, st);
    const size_t plane = (size_t)w * h;
    for (size_t p = 0; !rc && p < plane; p++)
        for (int c = 0; c < 3; c++)
            out->data[c * plane + p] = pixels[p * nc + (nc == 3 ? c : 0)] * (1.0f / 255.0f);
    free(pixels);
    return rc;
}

/* Replaces img by its resampling to width x height. */
static int resample_in_place(ws_image *img, int width, int height, ws_status *st) {
    ws_image full = *img;
    int rc = ws_image_resample(&full, width, height, img, st);
    ws_image_free(&full);
    return rc;
}

int ws_image_read(const char *path, int width, int height, const float background[3],
                  ws_image *out, ws_status *st) {
    return ws_image_read_alpha(path, width, height, background, out, NULL, st);
}

int ws_image_read_alpha(const char *path, int width, int height, const float background[3],
                        ws_image *out, ws_image *alpha, ws_status *st) {
    int reduced, file_size[2];
    int rc = ws_image_read_reduced(path, 1, background, out, alpha, &reduced, file_size, st);
    if (!rc && width > 0 && height > 0 && (out->width != width || out->height != height)) {
        rc = resample_in_place(out, width, height, st);
        if (!rc && alpha && alpha->data) rc = resample_in_place(alpha, width, height, st);
        if (rc) {
            ws_image_free(out);
            if (alpha) ws_image_free(alpha);
        }
    }
    return rc;
}

/* The image format a file's first 12 bytes name, among those a capture's
 * photos come in that are not read here (a phone's HEIC, a raw camera's
 * TIFF-based files, a web export's WebP); NULL for none of them. */
static const char *other_image_format(const unsigned char *head, size_t n) {
    static const struct {
        const char *name;
        int at, len;
        const char *magic, *riff; /* riff: "RIFF" when the file must open with it, else NULL */
    } formats[] = {{"a GIF", 0, 4, "GIF8", NULL},
                   {"a HEIC", 4, 8, "ftypheic", NULL},
                   {"a HEIC", 4, 8, "ftypheix", NULL},
                   {"a HEIC", 4, 8, "ftyphevc", NULL},
                   {"a HEIF", 4, 8, "ftypmif1", NULL},
                   {"a HEIF", 4, 8, "ftypmsf1", NULL},
                   {"an AVIF", 4, 8, "ftypavif", NULL},
                   {"a WebP", 8, 4, "WEBP", "RIFF"},
                   {"a TIFF", 0, 4, "II*\0", NULL},
                   {"a TIFF", 0, 4, "MM\0*", NULL},
                   {"a BMP", 0, 2, "BM", NULL},
                   {"an OpenEXR", 0, 4, "\x76\x2f\x31\x01", NULL},
                   {"a JPEG 2000", 4, 4, "jP  ", NULL}};
    for (size_t k = 0; k < sizeof formats / sizeof formats[0]; k++)
        if ((size_t)(formats[k].at + formats[k].len) <= n &&
            !memcmp(head + formats[k].at, formats[k].magic, (size_t)formats[k].len) &&
            (!formats[k].riff || !memcmp(head, formats[k].riff, 4)))
            return formats[k].name;
    return NULL;
}

int ws_image_read_reduced(const char *path, int reduce, const float background[3], ws_image *out,
                          ws_image *alpha, int *reduced, int file_size[2], ws_status *st) {
    *out = (ws_image){0};
    *reduced = 1;
    if (alpha) *alpha = (ws_image){0};
    FILE *fp;
    if (ws_fopen_regular(path, MAX_PNG_FILE_BYTES, &fp, st)) return st->code;
    png_byte sig[8];
    size_t got = fread(sig, 1, sizeof sig, fp);
    static const png_byte jpeg_sig[3] = {0xFF, 0xD8, 0xFF}; /* SOI, then a marker */
    int rc;
    if (got < sizeof sig && ferror(fp))
        rc = ws_fail(st, WS_EINPUT, "%s: cannot read: %s", path, strerror(errno));
    else if (got == sizeof sig && !png_sig_cmp(sig, 0, sizeof sig)) {
        rc = decode_png(fp, path, *reduced = reduce, background, out, alpha, file_size, st);
    } else if (got >= 3 && !memcmp(sig, jpeg_sig, 3) && fseek(fp, 0, SEEK_SET) == 0)
        rc = decode_jpeg(fp, path, *reduced = reduce, out, file_size, st);
    else {
        unsigned char head[12];
        memcpy(head, sig, got);
        got += fread(head + got, 1, sizeof head - got, fp);
        const char *format = other_image_format(head, got);
        if (format)
            rc = ws_fail(st, WS_EINPUT, "%s: %s image, not PNG or JPEG (convert it to JPEG or PNG)", path, format);
        else
            rc = ws_fail(st, WS_EINPUT, "%s: not a PNG or JPEG file", path);
    }
    fclose(fp);
    if (rc) {
        ws_image_free(out);
        if (alpha) ws_image_free(alpha);
    }
    return rc;
}

/* Our own write function, so that a failed write says why (errno: "No
 * space left on device") instead of libpng's "Write Error". */
static void write_data(png_structp png, png_bytep data, size_t length) {
    png_io *io = png_get_io_ptr(png);
    if (fwrite(data, 1, length, io->fp) != length) png_error(png, strerror(errno ? errno : EIO));
}

static void flush_data(png_structp png) {}

/* Stage of the writer: everything from the header to the end chunk. */
static int write_stage(png_structp png, png_infop info, const ws_image *img, png_bytep row,
                       png_io *io) {
    if (setjmp(png_jmpbuf(png))) return -1;
    const int w = img->width, h = img->height, nc = img->channels;
    png_set_write_fn(png, io, write_data, flush_data);
    png_set_IHDR(png, info, w, h, 8, nc == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int i = 0; i < h; i++) {
        for (int j = 0; j < w; j++)
            for (int c = 0; c < nc; c++) {
                float v = img->data[((size_t)c * h + i) * w + j];
                v = v > 0 ? (v < 1 ? v : 1) : 0; /* also maps NaN to 0 */
                row[j * nc + c] = (png_byte)(255.0f * v + 0.5f);
            }
        png_write_row(png, row);
    }
    png_write_end(png, info);
    return 0;
}

int ws_png_write(const char *path, const ws_image *img, ws_status *st) {
    if (img->channels != 1 && img->channels != 3)
        return ws_fail(st, WS_EINTERNAL, "%s: cannot write a %d-channel image as PNG", path,
                       img->channels);
    png_bytep row = ws_malloc((size_t)img->width * img->channels, path, st);
    if (!row) return st->code;
    png_io io = {NULL, ""};
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &io, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    ws_outfile f;
    int rc = WS_OK;
    if (!info)
        rc = ws_fail(st, WS_ENOMEM, "%s: out of memory creating a PNG encoder", path);
    else if (!(rc = ws_outfile_open(&f, path, st))) {
        io.fp = f.fp;
        if (write_stage(png, info, img, row, &io)) {
            ws_outfile_abort(&f);
            rc = ws_fail(st, WS_EIO, "%s: write failed: %s", path, io.reason);
        } else {
            rc = ws_outfile_commit(&f, st);
        }
    }
    png_destroy_write_struct(png ? &png : NULL, info ? &info : NULL);
    free(row);
    return rc;
}

int ws_image_write_jpeg(const char *path, const ws_image *img, int quality, ws_status *st) {
    if (img->channels != 1 && img->channels != 3)
        return ws_fail(st, WS_EINTERNAL, "%s: cannot write a %d-channel image as JPEG", path,
                       img->channels);
    const int w = img->width, h = img->height, nc = img->channels;
    unsigned char *pixels = ws_malloc((size_t)w * h * nc, path, st);
    if (!pixels) return st->code;
    const size_t plane = (size_t)w * h;
    for (size_t p = 0; p < plane; p++)
        for (int c = 0; c < nc; c++) {
            float v = img->data[c * plane + p];
            v = v > 0 ? (v < 1 ? v : 1) : 0; /* also maps NaN to 0 */
            pixels[p * nc + c] = (unsigned char)(255.0f * v + 0.5f);
        }
    int rc = ws_jpeg_encode(path, pixels, w, h, nc, quality, st);
    free(pixels);
    return rc;
}

/* ---------------------------------------------------------------- resampling */

/* One axis of a separable resampling: output sample o is
 * sum_k weight[o * taps + k] * input[first[o] + k]. */
typedef struct {
    int taps;
    int *first;
    float *weight;
} axis_filter;

/* Shrinking (or same size): output pixel o covers the input interval
 * [o s, (o + 1) s), s = in / out; each input pixel weighs its overlap / s.
 * Enlarging: bilinear at x = (o + 1/2) / (out / in) - 1/2 (pixel centres
 * aligned, as PIL and torchvision do), clamped at the borders. */
static int axis_filter_build(axis_filter *f, int in, int out, ws_status *st) {
    f->taps = in >= out ? (in + out - 1) / out + 1 : 2;
    f->first = ws_malloc(sizeof *f->first * out, "a resampling filter", st);
    f->weight = f->first
                    ? ws_calloc((size_t)out * f->taps, sizeof *f->weight, "a resampling filter", st)
                    : NULL;
    if (!f->weight) {
        free(f->first);
        return st->code;
    }
    const double s = (double)in / out;
    for (int o = 0; o < out; o++) {
        float *w = f->weight + (size_t)o * f->taps;
        if (in >= out) {
            double lo = o * s, hi = (o + 1) * s;
            int k0 = (int)floor(lo);
            f->first[o] = k0;
            for (int k = 0; k < f->taps && k0 + k < in; k++) {
                double overlap = fmin(hi, k0 + k + 1) - fmax(lo, k0 + k);
                w[k] = overlap > 0 ? (float)(overlap / s) : 0.0f;
            }
        } else {
            double x = fmin(fmax((o + 0.5) * s - 0.5, 0.0), in - 1.0);
            int k0 = (int)floor(x);
            if (k0 > in - 2) k0 = in > 1 ? in - 2 : 0;
            f->first[o] = k0;
            w[0] = (float)(1.0 - (x - k0));
            if (in > 1) w[1] = (float)(x - k0);
        }
    }
    return WS_OK;
}

static void axis_filter_free(axis_filter *f) {
    free(f->first);
    free(f->weight);
}

int ws_image_resample(const ws_image *in, int width, int height, ws_image *out, ws_status *st) {
    out->data = NULL;
    if (width <= 0 || height <= 0)
        return ws_fail(st, WS_EINTERNAL, "resample: size %d x %d is not positive", width, height);
    axis_filter fx, fy;
    if (axis_filter_build(&fx, in->width, width, st)) return st->code;
    if (axis_filter_build(&fy, in->height, height, st)) {
        axis_filter_free(&fx);
        return st->code;
    }
    const int nc = in->channels, w0 = in->width, h0 = in->height;
    ws_image tmp = {0}; /* horizontal pass: nc x h0 x width */
    int rc = ws_image_alloc(&tmp, width, h0, nc, st);
    if (!rc) rc = ws_image_alloc(out, width, height, nc, st);
    if (!rc) {
        for (int r = 0; r < nc * h0; r++) {
            const float *src = in->data + (size_t)r * w0;
            for (int o = 0; o < width; o++) {
                const float *w = fx.weight + (size_t)o * fx.taps;
                double sum = 0;
                for (int k = 0; k < fx.taps && fx.first[o] + k < w0; k++)
                    sum += w[k] * src[fx.first[o] + k];
                tmp.data[(size_t)r * width + o] = (float)sum;
            }
        }
        for (int c = 0; c < nc; c++)
            for (int o = 0; o < height; o++) {
                const float *w = fy.weight + (size_t)o * fy.taps;
                float *dst = out->data + ((size_t)c * height + o) * width;
                for (int j = 0; j < width; j++) dst[j] = 0;
                for (int k = 0; k < fy.taps && fy.first[o] + k < h0; k++) {
                    const float *src = tmp.data + ((size_t)c * h0 + fy.first[o] + k) * width;
                    for (int j = 0; j < width; j++) dst[j] += w[k] * src[j];
                }
            }
    }
    ws_image_free(&tmp);
    axis_filter_free(&fx);
    axis_filter_free(&fy);
    return rc;
}

int ws_image_crop(const ws_image *in, int x0, int y0, int width, int height, ws_image *out,
                  ws_status *st) {
    if (x0 < 0 || y0 < 0 || width < 1 || height < 1 || x0 + width > in->width ||
        y0 + height > in->height)
        return ws_fail(st, WS_EINTERNAL, "crop %d x %d at (%d, %d) leaves a %d x %d image", width,
                       height, x0, y0, in->width, in->height);
    if (ws_image_alloc(out, width, height, in->channels, st)) return st->code;
    for (int c = 0; c < in->channels; c++)
        for (int i = 0; i < height; i++)
            memcpy(out->data + ((size_t)c * height + i) * width,
                   in->data + ((size_t)c * in->height + y0 + i) * in->width + x0,
                   sizeof(float) * width);
    return WS_OK;
}

static int compare_floats(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

void ws_image_border_median(const ws_image *img, float out[3], float *scratch) {
    const int w = img->width, h = img->height;
    for (int c = 0; c < 3; c++) {
        const float *plane = img->data + (size_t)c * w * h;
        int n = 0;
        for (int i = 0; i < h; i++)
            for (int j = 0; j < w; j += (i == 0 || i == h - 1 || j == w - 1) ? 1 : w - 1)
                scratch[n++] = plane[(size_t)i * w + j];
        qsort(scratch, n, sizeof *scratch, compare_floats);
        out[c] = scratch[n / 2];
    }
}
