/* gif.h: animated GIF output (giflib), written frame by frame.
 *
 * Frames are streamed into the file as they come, so an animation of any
 * length costs one row of memory; the file appears (renamed from its
 * temporary name, see outfile.h) only at ws_gif_commit. Pixels are 8-bit,
 * row-major and interleaved: 1 channel (gray, 256 exact grays) or 3 (RGB,
 * mapped to the nearest colour of a fixed 6 x 7 x 6 cube, no dithering).
 * The animation loops forever (NETSCAPE2.0 extension).
 *
 *     ws_gif gif;
 *     if (ws_gif_open(&gif, "evolution.gif", 224, 224, 1, 10, st)) return st->code;
 *     for (...) if (ws_gif_add_frame(&gif, gray, st)) return st->code;
 *     if (ws_gif_commit(&gif, st)) return st->code;
 *
 * After a failure the GIF is already abandoned (temporary file removed);
 * ws_gif_abort is safe to call at any time, also twice, to abandon it on
 * another error path. */
#ifndef WS_GIF_H
#define WS_GIF_H
#include "base/outfile.h"
#include "nn/base/status.h"

struct GifFileType;

typedef struct {
    ws_outfile out;
    struct GifFileType *gif; /* NULL once committed or abandoned */
    int width, height, channels;
    int delay_cs;            /* per frame, in 1/100 s */
    int frames;              /* frames written so far */
    unsigned char *line;     /* one row of palette indices */
} ws_gif;

/* Opens PATH (through its temporary name) for frames of width x height x
 * channels (1 or 3); delay_cs is the time each frame shows, in 1/100 s
 * (browsers show delays below 2 as 10). */
int ws_gif_open(ws_gif *g, const char *path, int width, int height, int channels, int delay_cs,
                ws_status *st);

/* pixels: height x width x channels bytes. */
int ws_gif_add_frame(ws_gif *g, const unsigned char *pixels, ws_status *st);

/* Ends the file and renames it onto PATH. A GIF needs at least one frame. */
int ws_gif_commit(ws_gif *g, ws_status *st);

void ws_gif_abort(ws_gif *g);

#endif
