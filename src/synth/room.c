/* room.c: the box room behind a synthetic object (see room.h). */
#include <math.h>
#include "synth/room.h"

/* The pattern at point (a, b) of a face, its two in-plane coordinates in
 * world units from the room's centre (b up on a wall). */
static void floor_colour(double a, double b, float rgb[3]) {
    static const float tile[2][3] = {{0.62f, 0.48f, 0.33f}, {0.36f, 0.27f, 0.20f}};
    static const float grout[3] = {0.08f, 0.08f, 0.09f}, rug[3] = {0.55f, 0.12f, 0.15f};
    const double fa = a - floor(a), fb = b - floor(b);
    const float *c = tile[((long)floor(a) + (long)floor(b)) & 1];
    if (fa < 0.04 || fb < 0.04) c = grout;
    if (fabs(a - 2.5) < 1.6 && fabs(b + 1.5) < 1.0 && fmod(fabs(a) * 5, 1) > 0.25) c = rug;
    for (int k = 0; k < 3; k++) rgb[k] = c[k];
}

/* b_floor: the floor's height on a wall's b axis (the skirting runs along it). */
static void wall_colour(int wall, double a, double b, double b_floor, float rgb[3]) {
    static const float tone[4][2][3] = {{{0.80f, 0.78f, 0.62f}, {0.66f, 0.60f, 0.45f}},
                                        {{0.45f, 0.62f, 0.72f}, {0.30f, 0.45f, 0.58f}},
                                        {{0.70f, 0.72f, 0.70f}, {0.52f, 0.55f, 0.50f}},
                                        {{0.76f, 0.60f, 0.60f}, {0.58f, 0.40f, 0.42f}}};
    static const double period[4] = {0.8, 0.55, 1.3, 0.4};
    static const float skirting[3] = {0.93f, 0.93f, 0.90f}, frame[3] = {0.10f, 0.07f, 0.05f};
    static const float picture[3][3] = {{0.20f, 0.45f, 0.25f}, {0.85f, 0.75f, 0.30f}, {0.25f, 0.25f, 0.55f}};
    const double s = a / period[wall];
    const float *c = tone[wall][(s - floor(s)) < 0.5];
    if (b < b_floor + 0.4) c = skirting;
    for (int p = 0; p < 3; p++) { /* pictures: a dark frame around a canvas */
        const double pa = -4.5 + 4.0 * p + wall, pb = 0.8 + 0.6 * ((p + wall) % 2), half_a = 1.0, half_b = 0.7;
        const double da = fabs(a - pa), db = fabs(b - pb);
        if (da < half_a && db < half_b) c = da > half_a - 0.12 || db > half_b - 0.12 ? frame : picture[(p + wall) % 3];
    }
    for (int k = 0; k < 3; k++) rgb[k] = c[k];
}

static void ceiling_colour(double a, double b, float rgb[3]) {
    const double fa = a / 2 - floor(a / 2), fb = b / 2 - floor(b / 2);
    const float v = fa < 0.03 || fb < 0.03 ? 0.45f : 0.88f;
    for (int k = 0; k < 3; k++) rgb[k] = v;
}

void ws_room_colour(const double center[3], double floor_z, const double origin[3], const double dir[3],
                    float rgb[3]) {
    const double lo[3] = {center[0] - WS_ROOM_HALF, center[1] - WS_ROOM_HALF, floor_z};
    const double hi[3] = {center[0] + WS_ROOM_HALF, center[1] + WS_ROOM_HALF, center[2] + WS_ROOM_HALF};
    for (int a = 0; a < 3; a++)
        if (!(origin[a] > lo[a] && origin[a] < hi[a])) {
            rgb[0] = rgb[1] = rgb[2] = 0.5f;
            return;
        }
    /* From inside, the ray leaves through the face it reaches first. */
    double t = INFINITY;
    int face = -1; /* 2 a + (1 for the high side) */
    for (int a = 0; a < 3; a++) {
        if (dir[a] == 0) continue;
        const double ta = ((dir[a] > 0 ? hi[a] : lo[a]) - origin[a]) / dir[a];
        if (ta < t) t = ta, face = 2 * a + (dir[a] > 0);
    }
    if (face < 0) { /* a zero direction sees nothing in particular */
        rgb[0] = rgb[1] = rgb[2] = 0.5f;
        return;
    }
    double p[3];
    for (int a = 0; a < 3; a++) p[a] = origin[a] + t * dir[a] - center[a];
    if (face == 4)
        floor_colour(p[0], p[1], rgb);
    else if (face == 5)
        ceiling_colour(p[0], p[1], rgb);
    else /* walls 0 .. 3: x low, x high, y low, y high; along the other horizontal axis */
        wall_colour(face, face < 2 ? p[1] : p[0], p[2], floor_z - center[2], rgb);
}

int ws_room_render(const ws_camera *cam, const double center[3], double floor_z, int supersample, ws_image *img,
                   ws_status *st) {
    if (supersample < 1 || supersample > 16)
        return ws_fail(st, WS_EINTERNAL, "room: supersampling %d is not in [1, 16]", supersample);
    const int W = cam->width, H = cam->height, ss = supersample;
    if (ws_image_alloc(img, W, H, 3, st)) return st->code;
    double origin[3];
    ws_camera_position(cam, origin);
    const size_t plane = (size_t)W * H;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            double sum[3] = {0, 0, 0};
            for (int a = 0; a < ss; a++)
                for (int b = 0; b < ss; b++) {
                    double D[3], dir[3];
                    ws_camera_pixel_ray(cam, i + (a + 0.5) / ss - 0.5, j + (b + 0.5) / ss - 0.5, D);
                    for (int k = 0; k < 3; k++)
                        dir[k] = cam->c2w[k][0] * D[0] + cam->c2w[k][1] * D[1] + cam->c2w[k][2] * D[2];
                    float rgb[3];
                    ws_room_colour(center, floor_z, origin, dir, rgb);
                    for (int k = 0; k < 3; k++) sum[k] += rgb[k];
                }
            for (int k = 0; k < 3; k++) img->data[k * plane + (size_t)i * W + j] = (float)(sum[k] / (ss * ss));
        }
    return WS_OK;
}
