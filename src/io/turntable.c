/* turntable.c: sketch renders and the fly-around GIF (see turntable.h). */
#include <math.h>
#include <stdlib.h>
#include "io/gif.h"
#include "io/turntable.h"

/* Seconds one turn of the turntable takes. */
#define TURN_SECONDS 6.0

int ws_sketch_renderer_init(ws_sketch_renderer *r, int width, int height, ws_status *st) {
    *r = (ws_sketch_renderer){.width = width, .height = height};
    size_t npix = (size_t)width * height;
    if (ws_splat_create(&r->splat, width, height, st) ||
        !(r->alpha = ws_malloc(npix * sizeof *r->alpha, "sketch render", st)) ||
        !(r->gray = ws_malloc(npix, "sketch render", st))) {
        ws_sketch_renderer_free(r);
        return st->code;
    }
    return WS_OK;
}

void ws_sketch_renderer_free(ws_sketch_renderer *r) {
    ws_splat_free(r->splat);
    ws_gaussians_free(&r->g);
    free(r->alpha);
    free(r->gray);
    *r = (ws_sketch_renderer){0};
}

int ws_sketch_render(ws_sketch_renderer *r, const ws_curves *c, const ws_camera *cam,
                     ws_status *st) {
    if (cam->width != r->width || cam->height != r->height)
        return ws_fail(st, WS_EINTERNAL, "sketch render: camera is %d x %d, renderer %d x %d",
                       cam->width, cam->height, r->width, r->height);
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    if (ws_curves_sample(c, &r->g, st) ||
        ws_splat_forward(r->splat, cam, r->g.mu, r->g.n, c->thickness, &opt, r->alpha, st))
        return st->code;
    size_t npix = (size_t)r->width * r->height;
    for (size_t k = 0; k < npix; k++) {
        double a = r->alpha[k];
        a = a > 0 ? (a < 1 ? a : 1) : 0; /* also maps NaN to no stroke */
        r->gray[k] = (unsigned char)lround(255.0 * (1.0 - a));
    }
    return WS_OK;
}

double ws_turntable_distance(const ws_split *split, const double center[3]) {
    double sum = 0;
    for (int k = 0; k < split->n; k++) {
        double pos[3];
        ws_camera_position(&split->views[k].cam, pos);
        sum += sqrt((pos[0] - center[0]) * (pos[0] - center[0]) +
                    (pos[1] - center[1]) * (pos[1] - center[1]) +
                    (pos[2] - center[2]) * (pos[2] - center[2]));
    }
    return split->n ? sum / split->n : 0;
}

int ws_turntable_camera(ws_camera *cam, const double center[3], double distance,
                        double camera_angle_x, int size, int i, int nframes, ws_status *st) {
    if (nframes < 1 || i < 0 || i >= nframes)
        return ws_fail(st, WS_EINTERNAL, "turntable: frame %d of %d", i, nframes);
    if (!(distance > 0) || !isfinite(distance))
        return ws_fail(st, WS_EINPUT, "turntable: camera distance %g is not positive", distance);
    double turn = 2 * M_PI * i / nframes;
    double azimuth = -M_PI / 2 + turn;
    double elevation = (-10 + 25 * (1 - cos(turn))) * M_PI / 180;
    /* back: the camera's +z, from the centre towards the camera (it looks
     * down -z); right = up_world x back is never degenerate because the
     * elevation stays within +-40 degrees; up = back x right. */
    double back[3] = {cos(elevation) * cos(azimuth), cos(elevation) * sin(azimuth), sin(elevation)};
    double right[3] = {-sin(azimuth), cos(azimuth), 0};
    double up[3] = {back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
                    back[0] * right[1] - back[1] * right[0]};
    double c2w[4][4] = {{0}};
    for (int r = 0; r < 3; r++) {
        c2w[r][0] = right[r];
        c2w[r][1] = up[r];
        c2w[r][2] = back[r];
        c2w[r][3] = center[r] + distance * back[r];
    }
    c2w[3][3] = 1;
    return ws_camera_init(cam, c2w, camera_angle_x, size, size, "turntable", st);
}

int ws_turntable_gif(const char *path, const ws_curves *c, const double center[3],
                     double distance, double camera_angle_x, int size, int nframes,
                     ws_drawing_render_fn render, void *ctx, ws_status *st) {
    if (nframes < 1) return ws_fail(st, WS_EUSAGE, "%s: turntable needs at least 1 frame", path);
    int delay_cs = (int)lround(100 * TURN_SECONDS / nframes);
    ws_sketch_renderer r;
    if (ws_sketch_renderer_init(&r, size, size, st)) return st->code;
    ws_gif gif;
    if (ws_gif_open(&gif, path, size, size, 1, delay_cs > 2 ? delay_cs : 2, st)) {
        ws_sketch_renderer_free(&r);
        return st->code;
    }
    for (int i = 0; i < nframes; i++) {
        ws_camera cam;
        if (ws_turntable_camera(&cam, center, distance, camera_angle_x, size, i, nframes, st) ||
            ws_sketch_render(&r, c, &cam, st) || (render && render(ctx, &cam, r.gray, r.gray, st)) ||
            ws_gif_add_frame(&gif, r.gray, st)) {
            ws_gif_abort(&gif);
            ws_sketch_renderer_free(&r);
            return st->code;
        }
    }
    ws_sketch_renderer_free(&r);
    return ws_gif_commit(&gif, st);
}
