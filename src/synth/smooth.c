/* smooth.c: smooth textured objects by sphere tracing (see smooth.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "synth/smooth.h"

#define AMBIENT 0.3
#define BOUND 1.0         /* every object lies within this radius of its centre */
#define MAX_STEPS 256
#define HIT 1e-4          /* distance that counts as on the surface */
#define NORMAL_STEP 1e-4  /* central differences of the distance function */
#define BLEND 0.06        /* the animal's smooth minimum */

static const char *const smooth_names[] = {"torus", "vase", "animal"};
static const int smooth_count = sizeof smooth_names / sizeof smooth_names[0];

int ws_smooth_exists(const char *name) {
    for (int k = 0; k < smooth_count; k++)
        if (!strcmp(name, smooth_names[k])) return 1;
    return 0;
}

int ws_smooth_make(ws_smooth *s, const char *name, const double center[3], ws_status *st) {
    for (int k = 0; k < smooth_count; k++)
        if (!strcmp(name, smooth_names[k])) {
            s->kind = k;
            memcpy(s->center, center, sizeof s->center);
            return WS_OK;
        }
    return ws_fail(st, WS_EUSAGE, "%s: unknown smooth object (torus, vase, animal)", name);
}

static double capsule(const double p[3], const double a[3], const double b[3], double r) {
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double h = (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / (ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
    h = fmin(fmax(h, 0), 1);
    double d[3] = {ap[0] - h * ab[0], ap[1] - h * ab[1], ap[2] - h * ab[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - r;
}

/* Polynomial smooth minimum (a lower bound of a distance stays one). */
static double smin(double a, double b, double k) {
    double h = fmax(k - fabs(a - b), 0) / k;
    return fmin(a, b) - h * h * k / 4;
}

static double vase_radius(double z) { return 0.32 + 0.14 * sin(4.2 * z + 0.9); }

/* The animal's parts: capsules (a, b, radius). */
static const double ANIMAL[][7] = {
    {-0.45, 0, 0.05, 0.35, 0, 0.05, 0.22},     /* body */
    {0.25, 0.12, -0.05, 0.27, 0.13, -0.55, 0.07}, {0.25, -0.12, -0.05, 0.27, -0.13, -0.55, 0.07},
    {-0.35, 0.12, -0.05, -0.37, 0.13, -0.55, 0.07}, {-0.35, -0.12, -0.05, -0.37, -0.13, -0.55, 0.07},
    {0.3, 0, 0.1, 0.5, 0, 0.38, 0.09},         /* neck */
    {0.5, 0, 0.42, 0.72, 0, 0.36, 0.12},       /* head */
    {-0.6, 0, 0.1, -0.78, 0, 0.3, 0.04},       /* tail */
};

/* Signed distance (or a lower bound of it) to the object, p relative to its centre. */
static double sdf(int kind, const double p[3]) {
    if (kind == 0) {
        double q = sqrt(p[0] * p[0] + p[1] * p[1]) - 0.55;
        return sqrt(q * q + p[2] * p[2]) - 0.2;
    }
    if (kind == 1) /* |d r / dz| <= 0.59: the radial gap times cos(atan 0.59) bounds the distance */
        return fmax(0.86 * (sqrt(p[0] * p[0] + p[1] * p[1]) - vase_radius(p[2])), fabs(p[2]) - 0.6);
    double d = INFINITY;
    for (size_t k = 0; k < sizeof ANIMAL / sizeof ANIMAL[0]; k++) {
        double c = capsule(p, ANIMAL[k], ANIMAL[k] + 3, ANIMAL[k][6]);
        d = k ? smin(d, c, BLEND) : c;
    }
    return d;
}

static uint32_t hash3(int x, int y, int z, uint32_t salt) {
    uint32_t h = (uint32_t)x * 0x8da6b343u ^ (uint32_t)y * 0xd8163841u ^ (uint32_t)z * 0xcb1ab31fu ^ salt;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    return h ^ (h >> 15);
}

static double unit(uint32_t h) { return (h & 0xffffff) / 16777216.0; }

/* Trilinear value noise in [0, 1) at p / cell. */
static double value_noise(const double p[3], double cell) {
    double f[3];
    int c[3];
    for (int x = 0; x < 3; x++) {
        double s = p[x] / cell;
        c[x] = (int)floor(s);
        f[x] = s - c[x];
        f[x] = f[x] * f[x] * (3 - 2 * f[x]);
    }
    double v = 0;
    for (int k = 0; k < 8; k++) {
        int a = k & 1, b = (k >> 1) & 1, d = k >> 2;
        double w = (a ? f[0] : 1 - f[0]) * (b ? f[1] : 1 - f[1]) * (d ? f[2] : 1 - f[2]);
        v += w * unit(hash3(c[0] + a, c[1] + b, c[2] + d, 0x9e3779b9u));
    }
    return v;
}

/* The texture's albedo at p (relative to the centre). */
static void albedo(int kind, const double p[3], double rgb[3]) {
    static const double YELLOW[3] = {0.9, 0.75, 0.25}, BLUE[3] = {0.2, 0.35, 0.8};
    static const double CLAY[3] = {0.85, 0.5, 0.3}, DARK[3] = {0.2, 0.12, 0.08};
    static const double TAN[3] = {0.85, 0.7, 0.5}, BROWN[3] = {0.3, 0.18, 0.1};
    const double *c;
    if (kind == 0) {
        int stripe = (int)floor((atan2(p[1], p[0]) + M_PI) / (2 * M_PI) * 24);
        c = stripe % 2 ? YELLOW : BLUE;
    } else if (kind == 1) {
        const double cell = 0.18;
        int g[3] = {(int)floor(p[0] / cell), (int)floor(p[1] / cell), (int)floor(p[2] / cell)};
        int spot = 0;
        for (int k = 0; k < 27 && !spot; k++) {
            int x = g[0] + k % 3 - 1, y = g[1] + (k / 3) % 3 - 1, z = g[2] + k / 9 - 1;
            double s[3] = {(x + unit(hash3(x, y, z, 1))) * cell, (y + unit(hash3(x, y, z, 2))) * cell,
                           (z + unit(hash3(x, y, z, 3))) * cell};
            double d2 = (p[0] - s[0]) * (p[0] - s[0]) + (p[1] - s[1]) * (p[1] - s[1]) + (p[2] - s[2]) * (p[2] - s[2]);
            spot = d2 < 0.06 * 0.06;
        }
        c = spot ? DARK : CLAY;
    } else {
        double v = 0.65 * value_noise(p, 0.22) + 0.35 * value_noise(p, 0.09);
        c = v > 0.55 ? BROWN : TAN;
    }
    memcpy(rgb, c, 3 * sizeof *rgb);
}

/* The first hit of the ray o + t d (d unit) with the object, or INFINITY. */
static double trace(int kind, const double o[3], const double d[3]) {
    double b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2], c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - BOUND * BOUND;
    double disc = b * b - c;
    if (disc <= 0) return INFINITY;
    double t = fmax(0, -b - sqrt(disc)), t1 = -b + sqrt(disc);
    for (int k = 0; k < MAX_STEPS && t < t1; k++) {
        double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
        double s = sdf(kind, p);
        if (s < HIT) return t;
        t += s;
    }
    return INFINITY;
}

static void surface_normal(int kind, const double p[3], double n[3]) {
    double len = 0;
    for (int x = 0; x < 3; x++) {
        double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
        a[x] += NORMAL_STEP;
        b[x] -= NORMAL_STEP;
        n[x] = sdf(kind, a) - sdf(kind, b);
        len += n[x] * n[x];
    }
    len = sqrt(len);
    for (int x = 0; x < 3; x++) n[x] = len > 0 ? n[x] / len : 0;
}

int ws_smooth_render(const ws_smooth *s, const ws_camera *cam, int supersample, const float background[3],
                     ws_image *img, ws_geometry_buffer *g, ws_status *st) {
    if (supersample < 1 || supersample > 15 || supersample % 2 == 0)
        return ws_fail(st, WS_EINTERNAL, "smooth: supersampling %d is not odd in [1, 15]", supersample);
    const int ss = supersample, W = cam->width, H = cam->height;
    if (g && (g->width != W || g->height != H))
        return ws_fail(st, WS_EINTERNAL, "smooth: geometry buffer %d x %d, camera %d x %d", g->width, g->height, W, H);
    if (ws_image_alloc(img, W, H, 3, st)) return st->code;
    const size_t plane = (size_t)W * H;
    double pos[3], o[3];
    ws_camera_position(cam, pos);
    for (int x = 0; x < 3; x++) o[x] = pos[x] - s->center[x];
    const double lw[3] = {0.3, -0.5, 0.8}, ll = sqrt(lw[0] * lw[0] + lw[1] * lw[1] + lw[2] * lw[2]);
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            double sum[3] = {0, 0, 0};
            int hits = 0;
            size_t at = (size_t)i * W + j;
            if (g) {
                g->depth[at] = INFINITY;
                for (int c = 0; c < 3; c++) g->normal[c * plane + at] = 0;
            }
            for (int a = 0; a < ss; a++)
                for (int b = 0; b < ss; b++) {
                    /* camera-space direction with D_z = -1 (camera.h), then world */
                    double u = j + (b + 0.5) / ss, v = i + (a + 0.5) / ss;
                    double D[3] = {(u - cam->cx) / cam->focal, -(v - cam->cy) / cam->focal, -1}, d[3];
                    for (int x = 0; x < 3; x++) d[x] = cam->R[0][x] * D[0] + cam->R[1][x] * D[1] + cam->R[2][x] * D[2];
                    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                    for (int x = 0; x < 3; x++) d[x] /= len;
                    double t = trace(s->kind, o, d);
                    if (!isfinite(t)) {
                        for (int c = 0; c < 3; c++) sum[c] += background[c];
                        continue;
                    }
                    hits++;
                    double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}, n[3], rgb[3];
                    surface_normal(s->kind, p, n);
                    albedo(s->kind, p, rgb);
                    double lambert = fmax(0, (n[0] * lw[0] + n[1] * lw[1] + n[2] * lw[2]) / ll);
                    for (int c = 0; c < 3; c++) sum[c] += rgb[c] * (AMBIENT + (1 - AMBIENT) * lambert);
                    if (g && a == ss / 2 && b == ss / 2) {
                        g->depth[at] = (float)(t / len); /* along D: the camera-space depth */
                        for (int c = 0; c < 3; c++) g->normal[c * plane + at] = (float)n[c];
                    }
                }
            for (int c = 0; c < 3; c++) img->data[c * plane + at] = (float)(sum[c] / (ss * ss));
            if (g) g->coverage[at] = (float)hits / (ss * ss);
        }
    return WS_OK;
}
