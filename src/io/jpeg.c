/* jpeg.c: JPEG input/output through libjpeg-turbo (see jpeg.h).
 *
 * libjpeg reports errors through error_exit, which must not return: ours
 * records the reason and longjmps back into the one small stage function
 * that made the call, as image.c does for libpng (each stage has its own
 * setjmp and changes no local variable after it; all allocation happens
 * outside the stages). Warnings are made errors too: libjpeg warns, and
 * goes on with grey rows, when a file ends early or its data is corrupt. */
#include <errno.h>
#include <setjmp.h>
#include <stdio.h> /* before jpeglib.h, which uses FILE */
#include <stdlib.h>
#include <string.h>
#include <jpeglib.h>
#include "io/jpeg.h"
#include "base/outfile.h"

typedef struct {
    struct jpeg_error_mgr mgr; /* first: libjpeg's pointer to it is ours */
    jmp_buf jump;
    char reason[JMSG_LENGTH_MAX];
} jpeg_errors;

static void on_jpeg_error(j_common_ptr cinfo) {
    jpeg_errors *e = (jpeg_errors *)cinfo->err;
    e->mgr.format_message(cinfo, e->reason);
    longjmp(e->jump, 1);
}

/* msg_level -1 is a warning (corrupt or missing data), >= 0 trace output. */
static void on_jpeg_message(j_common_ptr cinfo, int msg_level) {
    if (msg_level < 0) on_jpeg_error(cinfo);
}

static void errors_init(jpeg_errors *e) {
    jpeg_std_error(&e->mgr);
    e->mgr.error_exit = on_jpeg_error;
    e->mgr.emit_message = on_jpeg_message;
    e->reason[0] = '\0';
}

/* Stage 1: the header (markers up to the first scan). */
static int read_header_stage(struct jpeg_decompress_struct *cinfo, FILE *fp) {
    jpeg_errors *e = (jpeg_errors *)cinfo->err;
    if (setjmp(e->jump)) return -1;
    jpeg_create_decompress(cinfo);
    jpeg_stdio_src(cinfo, fp);
    jpeg_read_header(cinfo, TRUE);
    return 0;
}

/* Stage 1b: the output's size at 1 / reduce of the file's, as libjpeg's
 * scaled inverse DCT makes it (each 8 x 8 block straight to 8 / reduce
 * pixels a side: the pixels it leaves out are never made). */
static int scale_stage(struct jpeg_decompress_struct *cinfo, int reduce) {
    jpeg_errors *e = (jpeg_errors *)cinfo->err;
    if (setjmp(e->jump)) return -1;
    cinfo->scale_num = 1;
    cinfo->scale_denom = (unsigned)reduce;
    jpeg_calc_output_dimensions(cinfo);
    return 0;
}

/* Stage 2: every scanline into `pixels` (height rows of width * components
 * bytes), then the end of the file. */
static int read_pixels_stage(struct jpeg_decompress_struct *cinfo, JSAMPLE *pixels) {
    jpeg_errors *e = (jpeg_errors *)cinfo->err;
    if (setjmp(e->jump)) return -1;
    jpeg_start_decompress(cinfo);
    const size_t stride = (size_t)cinfo->output_width * cinfo->output_components;
    while (cinfo->output_scanline < cinfo->output_height) {
        JSAMPROW row = pixels + stride * cinfo->output_scanline;
        jpeg_read_scanlines(cinfo, &row, 1);
    }
    jpeg_finish_decompress(cinfo);
    return 0;
}

int ws_jpeg_decode(FILE *fp, const char *path, int max_side, uint64_t max_pixels, int reduce,
                   unsigned char **pixels_out, int *width, int *height, int *channels, int file_size[2],
                   ws_status *st) {
    *pixels_out = NULL;
    struct jpeg_decompress_struct cinfo;
    jpeg_errors e;
    errors_init(&e);
    memset(&cinfo, 0, sizeof cinfo);
    cinfo.err = &e.mgr;
    JSAMPLE *pixels = NULL;
    int rc = WS_OK;
    if (read_header_stage(&cinfo, fp)) {
        rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt JPEG (%s)", path, e.reason);
        goto done;
    }
    const unsigned w = cinfo.image_width, h = cinfo.image_height;
    if (w > (unsigned)max_side || h > (unsigned)max_side || (uint64_t)w * h > max_pixels) {
        rc = ws_fail(st, WS_EINPUT, "%s: image too large (%u x %u pixels)", path, w, h);
        goto done;
    }
    if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
        rc = ws_fail(st, WS_EINPUT, "%s: CMYK JPEG is not supported (convert it to RGB)", path);
        goto done;
    }
    const int gray = cinfo.jpeg_color_space == JCS_GRAYSCALE, nc = gray ? 1 : 3;
    cinfo.out_color_space = gray ? JCS_GRAYSCALE : JCS_RGB;
    if (scale_stage(&cinfo, reduce)) {
        rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt JPEG (%s)", path, e.reason);
        goto done;
    }
    const unsigned ow = cinfo.output_width, oh = cinfo.output_height;
    pixels = ws_malloc((size_t)ow * oh * nc, path, st);
    if (!pixels) {
        rc = st->code;
        goto done;
    }
    if (read_pixels_stage(&cinfo, pixels)) {
        rc = ws_fail(st, WS_EINPUT, "%s: truncated or corrupt JPEG (%s)", path, e.reason);
        goto done;
    }
    *pixels_out = pixels;
    pixels = NULL;
    *width = (int)ow;
    *height = (int)oh;
    *channels = nc;
    file_size[0] = (int)w;
    file_size[1] = (int)h;
done:
    jpeg_destroy_decompress(&cinfo);
    free(pixels);
    return rc;
}

/* The writer's one stage: header to end of image. */
static int write_stage(struct jpeg_compress_struct *cinfo, FILE *fp, const unsigned char *pixels,
                       int w, int h, int nc, int quality) {
    jpeg_errors *e = (jpeg_errors *)cinfo->err;
    if (setjmp(e->jump)) return -1;
    jpeg_create_compress(cinfo);
    jpeg_stdio_dest(cinfo, fp);
    cinfo->image_width = (JDIMENSION)w;
    cinfo->image_height = (JDIMENSION)h;
    cinfo->input_components = nc;
    cinfo->in_color_space = nc == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(cinfo);
    jpeg_set_quality(cinfo, quality, TRUE);
    for (int c = 0; c < cinfo->num_components; c++)
        cinfo->comp_info[c].h_samp_factor = cinfo->comp_info[c].v_samp_factor = 1;
    jpeg_start_compress(cinfo, TRUE);
    for (int i = 0; i < h; i++) {
        JSAMPROW row = (JSAMPROW)(pixels + (size_t)i * w * nc); /* libjpeg only reads it */
        jpeg_write_scanlines(cinfo, &row, 1);
    }
    jpeg_finish_compress(cinfo);
    return 0;
}

int ws_jpeg_encode(const char *path, const unsigned char *pixels, int width, int height,
                   int channels, int quality, ws_status *st) {
    if (channels != 1 && channels != 3)
        return ws_fail(st, WS_EINTERNAL, "%s: cannot write %d channels as JPEG", path, channels);
    struct jpeg_compress_struct cinfo;
    jpeg_errors e;
    errors_init(&e);
    memset(&cinfo, 0, sizeof cinfo);
    cinfo.err = &e.mgr;
    ws_outfile f;
    int rc = ws_outfile_open(&f, path, st);
    if (!rc) {
        if (write_stage(&cinfo, f.fp, pixels, width, height, channels, quality)) {
            ws_outfile_abort(&f);
            rc = ws_fail(st, WS_EIO, "%s: write failed: %s", path, e.reason);
        } else {
            rc = ws_outfile_commit(&f, st);
        }
    }
    jpeg_destroy_compress(&cinfo);
    return rc;
}
