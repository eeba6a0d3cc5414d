/* gif.c: streaming animated GIF writer on giflib (see gif.h). */
#include <gif_lib.h>
#include <stdlib.h>
#include "io/gif.h"

/* The RGB palette: levels per channel; 6 * 7 * 6 = 252 of the 256 entries,
 * green finest because the eye separates greens best. */
enum { CUBE_R = 6, CUBE_G = 7, CUBE_B = 6 };

static int write_to_outfile(GifFileType *gif, const GifByteType *buf, int len) {
    return (int)fwrite(buf, 1, (size_t)len, (FILE *)gif->UserData);
}

/* Nearest level of `levels` evenly spaced ones over 0..255. */
static int nearest_level(int v, int levels) {
    return (v * (levels - 1) + 127) / 255;
}

static void fill_palette(ColorMapObject *map, int channels) {
    for (int k = 0; k < 256; k++) {
        GifColorType *c = &map->Colors[k];
        if (channels == 1) {
            c->Red = c->Green = c->Blue = (GifByteType)k;
        } else if (k < CUBE_R * CUBE_G * CUBE_B) {
            int r = k / (CUBE_G * CUBE_B), g = k / CUBE_B % CUBE_G, b = k % CUBE_B;
            c->Red = (GifByteType)((r * 255 + (CUBE_R - 1) / 2) / (CUBE_R - 1));
            c->Green = (GifByteType)((g * 255 + (CUBE_G - 1) / 2) / (CUBE_G - 1));
            c->Blue = (GifByteType)((b * 255 + (CUBE_B - 1) / 2) / (CUBE_B - 1));
        } else {
            c->Red = c->Green = c->Blue = 0;
        }
    }
}

/* Abandons the GIF and reports giflib's error: `code`, or when that is 0
 * the error giflib recorded in the file handle. */
static int gif_fail(ws_gif *g, int code, const char *what, ws_status *st) {
    if (code == 0 && g->gif) code = g->gif->Error;
    const char *why = GifErrorString(code);
    ws_gif_abort(g);
    return ws_fail(st, WS_EIO, "%s: %s: %s", g->out.path, what, why ? why : "unknown giflib error");
}

int ws_gif_open(ws_gif *g, const char *path, int width, int height, int channels, int delay_cs,
                ws_status *st) {
    g->gif = NULL;
    g->line = NULL;
    g->out.fp = NULL;
    g->out.path[0] = g->out.tmp[0] = '\0'; /* nothing to remove yet */
    if (width < 1 || width > 65535 || height < 1 || height > 65535)
        return ws_fail(st, WS_EINTERNAL, "%s: GIF size %d x %d is not in 1..65535", path, width, height);
    if (channels != 1 && channels != 3)
        return ws_fail(st, WS_EINTERNAL, "%s: GIF frames need 1 or 3 channels, not %d", path, channels);
    if (delay_cs < 0 || delay_cs > 65535)
        return ws_fail(st, WS_EINTERNAL, "%s: GIF frame delay %d is not in 0..65535", path, delay_cs);
    g->width = width;
    g->height = height;
    g->channels = channels;
    g->delay_cs = delay_cs;
    g->frames = 0;
    g->line = ws_malloc((size_t)width, "GIF row", st);
    if (!g->line) return st->code;
    if (ws_outfile_open(&g->out, path, st)) {
        g->out.tmp[0] = '\0';
        ws_gif_abort(g);
        return st->code;
    }
    int err = 0;
    g->gif = EGifOpen(g->out.fp, write_to_outfile, &err);
    if (!g->gif) return gif_fail(g, err, "cannot start GIF", st);
    /* Streaming writes cannot look ahead at the extensions, so giflib would
     * label the file GIF87a; animation needs GIF89a. */
    EGifSetGifVersion(g->gif, true);
    ColorMapObject *map = GifMakeMapObject(256, NULL);
    if (!map) return gif_fail(g, E_GIF_ERR_NOT_ENOUGH_MEM, "cannot make palette", st);
    fill_palette(map, channels);
    int ok = EGifPutScreenDesc(g->gif, width, height, 8, 0, map) == GIF_OK;
    GifFreeMapObject(map);
    if (!ok) return gif_fail(g, 0, "cannot write GIF header", st);
    /* NETSCAPE2.0 application block: sub-block 1, loop count 0 = forever. */
    static const GifByteType loop[3] = {1, 0, 0};
    if (EGifPutExtensionLeader(g->gif, APPLICATION_EXT_FUNC_CODE) != GIF_OK ||
        EGifPutExtensionBlock(g->gif, 11, "NETSCAPE2.0") != GIF_OK ||
        EGifPutExtensionBlock(g->gif, 3, loop) != GIF_OK ||
        EGifPutExtensionTrailer(g->gif) != GIF_OK)
        return gif_fail(g, 0, "cannot write loop extension", st);
    return WS_OK;
}

int ws_gif_add_frame(ws_gif *g, const unsigned char *pixels, ws_status *st) {
    if (!g->gif) return ws_fail(st, WS_EINTERNAL, "%s: GIF is not open", g->out.path);
    GraphicsControlBlock gcb = {.DisposalMode = DISPOSE_DO_NOT, .UserInputFlag = false,
                                .DelayTime = g->delay_cs, .TransparentColor = NO_TRANSPARENT_COLOR};
    GifByteType ext[4];
    size_t len = EGifGCBToExtension(&gcb, ext);
    if (EGifPutExtension(g->gif, GRAPHICS_EXT_FUNC_CODE, (int)len, ext) != GIF_OK ||
        EGifPutImageDesc(g->gif, 0, 0, g->width, g->height, false, NULL) != GIF_OK)
        return gif_fail(g, 0, "cannot write frame header", st);
    for (int i = 0; i < g->height; i++) {
        const unsigned char *row = pixels + (size_t)i * g->width * g->channels;
        for (int j = 0; j < g->width; j++) {
            if (g->channels == 1) {
                g->line[j] = row[j];
            } else {
                const unsigned char *p = row + 3 * j;
                g->line[j] = (unsigned char)((nearest_level(p[0], CUBE_R) * CUBE_G +
                                              nearest_level(p[1], CUBE_G)) * CUBE_B +
                                             nearest_level(p[2], CUBE_B));
            }
        }
        if (EGifPutLine(g->gif, g->line, g->width) != GIF_OK)
            return gif_fail(g, 0, "cannot write frame", st);
    }
    g->frames++;
    return WS_OK;
}

int ws_gif_commit(ws_gif *g, ws_status *st) {
    if (!g->gif) return ws_fail(st, WS_EINTERNAL, "%s: GIF is not open", g->out.path);
    if (g->frames == 0) {
        ws_gif_abort(g);
        return ws_fail(st, WS_EINTERNAL, "%s: GIF has no frames", g->out.path);
    }
    int err = 0;
    int ok = EGifCloseFile(g->gif, &err) == GIF_OK; /* writes the trailer, frees the handle */
    g->gif = NULL;
    if (!ok) return gif_fail(g, err, "cannot end GIF", st);
    free(g->line);
    g->line = NULL;
    int rc = ws_outfile_commit(&g->out, st);
    g->out.tmp[0] = '\0'; /* renamed or removed: a later abort has nothing to do */
    return rc;
}

void ws_gif_abort(ws_gif *g) {
    if (g->gif) EGifCloseFile(g->gif, NULL);
    g->gif = NULL;
    free(g->line);
    g->line = NULL;
    if (g->out.tmp[0]) ws_outfile_abort(&g->out);
    g->out.tmp[0] = '\0';
}
