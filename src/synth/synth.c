/* synth.c: synthetic scenes, rendered by ray-casting tubes (see synth.h).
 *
 * A tube is drawn as a chain of capsules (a segment swept by a sphere of the
 * tube's radius) along a dense polyline of its Bezier curve. Each capsule is
 * rasterised over its own screen bounding box with a depth buffer, so the
 * cost follows the pixels the tubes cover, not pixels x capsules. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "base/outfile.h"
#include "base/paths.h"
#include "io/colmap.h"
#include "io/pointcloud.h"
#include "io/transforms.h"
#include "io/undistort.h"
#include "nn/base/rng.h"
#include "io/ref_lines.h"
#include "synth/line_drawing.h"
#include "synth/room.h"
#include "synth/smooth.h"
#include "synth/solids.h"
#include "synth/synth.h"

/* Blender's default camera (50 mm lens on a 36 mm sensor), as in the NeRF
 * synthetic scenes: about 0.691 radians. */
#define CAMERA_ANGLE_X (2.0 * atan(18.0 / 50.0))
/* Camera distance from the object's centre: a 1.5-unit object fills about
 * half of the view, as in ../shared/scenes, so that the default initial
 * radius 0.8 and thickness 0.02 of `fit` suit these scenes too. */
#define CAMERA_DISTANCE 4.0
/* The object's centre lies off the origin on purpose, so that nothing
 * downstream can rely on an origin-centred scene unnoticed. */
static const double OBJECT_CENTER[3] = {0.3, -0.2, 0.5};
/* rays per pixel: SUPERSAMPLE x SUPERSAMPLE, for smooth silhouettes */
#define SUPERSAMPLE 3
/* pinhole pixels per lens pixel of a view through a lens: bilinear
 * resampling of a render at twice the resolution keeps edges sharp */
#define LENS_OVERSAMPLE 2
#define JPEG_QUALITY 95
/* COLMAP's sparse cloud: points along the ground-truth curves with
 * Gaussian noise of this fraction of the object's size, and outliers (this
 * fraction of all points) uniform in a box three times the object's */
#define SPARSE_POINTS 2000
#define SPARSE_PLY "sparse_pc.ply" /* nerfstudio's name for them */
#define SPARSE_NOISE 0.005
#define SPARSE_OUTLIERS 0.1
#define AMBIENT 0.3
/* capsules per curve: about one per tube radius of arc length, within bounds */
#define MIN_CAPSULES_PER_CURVE 8
#define MAX_CAPSULES_PER_CURVE 512
/* surface points of a solid's gt_points.ply */
#define GT_POINTS 20000

/* The wire objects there are. */
static const char *const synth_names[] = {"trefoil", "chair", "spring", "flat"};
static const int synth_count = sizeof synth_names / sizeof synth_names[0];

void ws_synth_options_default(ws_synth_options *opt) {
    opt->views[WS_TRAIN] = 48;
    opt->views[WS_VAL] = 8;
    opt->views[WS_TEST] = 8;
    opt->size = 224;
    opt->seed = 0;
    opt->white_background = 0;
    opt->width = opt->height = 0;
    opt->room = opt->on_floor = opt->masks = 0;
    opt->principal[0] = opt->principal[1] = 0;
    opt->nerfstudio = 0;
    opt->colmap = 0;
    opt->jpeg = 0;
    for (int i = 0; i < 4; i++) opt->lens[i] = 0;
    opt->angle = CAMERA_ANGLE_X;
    opt->progress = NULL;
}

/* The image size of a scene, and the camera of view c2w: focal length from
 * the field of view over the shorter side, principal point at the centre
 * or opt->principal off it. */
static void image_size(const ws_synth_options *opt, int *w, int *h) {
    *w = opt->width ? opt->width : opt->size;
    *h = opt->height ? opt->height : opt->size;
}

static int synth_camera(const ws_synth_options *opt, const double c2w[4][4], const char *what,
                        ws_camera *cam, ws_status *st) {
    int w, h;
    image_size(opt, &w, &h);
    return ws_camera_init_pinhole(cam, c2w, 0.5 * (w < h ? w : h) / tan(0.5 * opt->angle),
                                  0.5 * w + opt->principal[0], 0.5 * h + opt->principal[1], w, h, what, st);
}

/* The lens of the views (opt->lens on synth_camera's intrinsics). */
static int synth_lens(const ws_synth_options *opt, const ws_camera *cam, ws_lens *lens,
                      ws_status *st) {
    memset(lens, 0, sizeof *lens);
    lens->fx = lens->fy = cam->focal;
    lens->cx = cam->cx;
    lens->cy = cam->cy;
    lens->width = cam->width;
    lens->height = cam->height;
    lens->k[0] = opt->lens[0], lens->k[1] = opt->lens[1];
    lens->p[0] = opt->lens[2], lens->p[1] = opt->lens[3];
    return ws_lens_check(lens, "--lens", st);
}

/* View k of split s: its image file, relative to the scene. */
static void view_file(const ws_synth_options *opt, int s, int k, char *out, size_t size) {
    const char *ext = opt->jpeg ? "jpg" : "png";
    if (opt->colmap)
        snprintf(out, size, "images/%s/r_%05d.%s", ws_split_names[s], k, ext);
    else
        snprintf(out, size, "rgb/%s/r_%d.%s", ws_split_names[s], k, ext);
}

/* View k's mask, relative to the scene: the scene loader's masks folder
 * (scene.h), masks/ with the image's name under its images folder and .png
 * for its extension ("masks/train/r_00003.png" for COLMAP's
 * "images/train/r_00003.jpg"). */
static void mask_file(const ws_synth_options *opt, int s, int k, char *out, size_t size) {
    char image[64];
    view_file(opt, s, k, image, sizeof image);
    const char *name = strchr(image, '/') + 1; /* below rgb/ or images/ */
    snprintf(out, size, "masks/%.*s.png", (int)(strrchr(name, '.') - name), name);
}

/* ---------------------------------------------------------------- objects */

static void set_curve(ws_curves *c, int ci, const double P[4][3]) {
    memcpy(c->P + (size_t)ci * WS_CURVE_FLOATS, P, WS_CURVE_FLOATS * sizeof(double));
}

/* A straight segment a -> b as a cubic: control points at 0, 1/3, 2/3, 1. */
static void set_line(ws_curves *c, int ci, const double a[3], const double b[3]) {
    double P[4][3];
    for (int j = 0; j < 4; j++)
        for (int x = 0; x < 3; x++) P[j][x] = a[x] + (b[x] - a[x]) * j / 3.0;
    set_curve(c, ci, P);
}

static void lerp3(const double a[3], const double b[3], double s, double out[3]) {
    for (int x = 0; x < 3; x++) out[x] = a[x] + s * (b[x] - a[x]);
}

/* A parametric space curve of a few shape numbers: its point p(t) and
 * derivative p'(t). */
typedef void (*param_curve)(double t, const double *shape, double p[3], double d[3]);

/* n cubic pieces of curve f over [t0, t1], scaled by `scale`, into curves
 * ci .. ci + n - 1: each the Hermite cubic of the curve's points and
 * tangents at its ends (P1 = p(a) + h/3 p'(a), P2 = p(b) - h/3 p'(b), h
 * the piece's parameter step), so the tangent is continuous throughout. */
static void add_pieces(ws_curves *c, int ci, int n, double t0, double t1, param_curve f,
                       const double *shape, double scale) {
    const double h = (t1 - t0) / n;
    for (int k = 0; k < n; k++) {
        double P[4][3];
        for (int end = 0; end < 2; end++) {
            double p[3], d[3], sign = end ? -1.0 : 1.0;
            f(t0 + (k + end) * h, shape, p, d);
            for (int x = 0; x < 3; x++) {
                P[3 * end][x] = scale * p[x];
                P[1 + end][x] = scale * (p[x] + sign * h / 3 * d[x]);
            }
        }
        set_curve(c, ci + k, P);
    }
}

/* The trefoil knot (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t). */
static void trefoil_curve(double t, const double *shape, double p[3], double d[3]) {
    (void)shape;
    p[0] = sin(t) + 2 * sin(2 * t);
    p[1] = cos(t) - 2 * cos(2 * t);
    p[2] = -sin(3 * t);
    d[0] = cos(t) + 4 * cos(2 * t);
    d[1] = -sin(t) + 4 * sin(2 * t);
    d[2] = -3 * cos(3 * t);
}

/* The trefoil scaled to about 1.6 units across, as 12 cubic pieces. */
#define TREFOIL_PIECES 12
static int make_trefoil(ws_synth_object *obj, ws_status *st) {
    if (ws_curves_alloc(&obj->curves, TREFOIL_PIECES, st)) return st->code;
    add_pieces(&obj->curves, 0, TREFOIL_PIECES, 0, 2 * M_PI, trefoil_curve, NULL, 0.27);
    obj->curves.thickness = 0.05;
    const float colour[3] = {0.95f, 0.55f, 0.2f};
    memcpy(obj->colour, colour, sizeof colour);
    return WS_OK;
}

/* A wire chair, z up, its back towards +y: four splayed legs, the seat's
 * square frame, two side stretchers, two back posts leaning back, a curved
 * top rail, a middle rail and a centre splat: 15 curves, 1.7 units tall. */
#define CHAIR_CURVES 15
static int make_chair(ws_synth_object *obj, ws_status *st) {
    if (ws_curves_alloc(&obj->curves, CHAIR_CURVES, st)) return st->code;
    ws_curves *c = &obj->curves;
    int ci = 0;
    double seat[4][3], foot[4][3]; /* corners: front-left, front-right, back-right, back-left */
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; k++) {
        double s[3] = {0.4 * sx[k], 0.4 * sy[k], 0.0}, f[3] = {0.44 * sx[k], 0.44 * sy[k], -0.8};
        memcpy(seat[k], s, sizeof s);
        memcpy(foot[k], f, sizeof f);
        set_line(c, ci++, seat[k], foot[k]);
    }
    for (int k = 0; k < 4; k++) set_line(c, ci++, seat[k], seat[(k + 1) % 4]);
    for (int side = 0; side < 2; side++) { /* left: legs 0 and 3; right: 1 and 2 */
        double a[3], b[3];
        lerp3(seat[side ? 1 : 0], foot[side ? 1 : 0], 0.6, a);
        lerp3(seat[side ? 2 : 3], foot[side ? 2 : 3], 0.6, b);
        set_line(c, ci++, a, b);
    }
    const double post_top[2][3] = {{-0.37, 0.5, 0.85}, {0.37, 0.5, 0.85}};
    set_line(c, ci++, seat[3], post_top[0]);
    set_line(c, ci++, seat[2], post_top[1]);
    const double top[4][3] = {
        {-0.37, 0.5, 0.85}, {-0.15, 0.62, 0.9}, {0.15, 0.62, 0.9}, {0.37, 0.5, 0.85}};
    set_curve(c, ci++, top);
    double mid_l[3], mid_r[3], mid_c[3], top_c[3];
    lerp3(seat[3], post_top[0], 0.45, mid_l);
    lerp3(seat[2], post_top[1], 0.45, mid_r);
    set_line(c, ci++, mid_l, mid_r);
    lerp3(mid_l, mid_r, 0.5, mid_c);
    ws_curve_point(c, ci - 2, 0.5, top_c);
    set_line(c, ci++, mid_c, top_c);
    c->thickness = 0.03;
    const float colour[3] = {0.85f, 0.65f, 0.4f};
    memcpy(obj->colour, colour, sizeof colour);
    return WS_OK;
}

/* The helix of radius shape[0] rising shape[1] per radian about the z axis. */
static void helix_curve(double t, const double *shape, double p[3], double d[3]) {
    p[0] = shape[0] * cos(t);
    p[1] = shape[0] * sin(t);
    p[2] = shape[1] * t;
    d[0] = -shape[0] * sin(t);
    d[1] = shape[0] * cos(t);
    d[2] = shape[1];
}

/* A wire spring, z up: a helix of radius 0.3 and 5 turns, 1 unit tall
 * (0.2 between turns), 4 cubic pieces a turn: 20 curves. */
#define SPRING_TURNS 5
#define SPRING_PIECES_PER_TURN 4
static int make_spring(ws_synth_object *obj, ws_status *st) {
    const int n = SPRING_TURNS * SPRING_PIECES_PER_TURN;
    if (ws_curves_alloc(&obj->curves, n, st)) return st->code;
    const double shape[2] = {0.3, 1.0 / (2 * M_PI * SPRING_TURNS)};
    add_pieces(&obj->curves, 0, n, 0, 2 * M_PI * SPRING_TURNS, helix_curve, shape, 1.0);
    obj->curves.thickness = 0.03;
    const float colour[3] = {0.75f, 0.78f, 0.85f};
    memcpy(obj->colour, colour, sizeof colour);
    return WS_OK;
}

/* The circle of centre (shape[0], shape[1]) and radius shape[2] in the
 * plane z = 0. */
static void circle_curve(double t, const double *shape, double p[3], double d[3]) {
    p[0] = shape[0] + shape[2] * cos(t);
    p[1] = shape[1] + shape[2] * sin(t);
    p[2] = 0;
    d[0] = -shape[2] * sin(t);
    d[1] = shape[2] * cos(t);
    d[2] = 0;
}

/* A flat wire object: a paper clip, 1.7 x 0.44 units, its four straight
 * legs joined by three U-turns (half circles of radius 0.1, 0.15 and 0.22,
 * two quarter pieces each; neighbouring wires 0.1 to 0.14 apart): 10
 * curves. Drawn in the plane z = 0, then tilted 40 degrees about its long
 * axis and turned 30 degrees about z, so that the training views that lie
 * near the great circle of directions in its plane see it nearly edge-on,
 * a thin line. */
#define FLAT_CURVES 10
static int make_flat(ws_synth_object *obj, ws_status *st) {
    if (ws_curves_alloc(&obj->curves, FLAT_CURVES, st)) return st->code;
    ws_curves *c = &obj->curves;
    /* legs: from the inner free end out, alternating direction */
    const double leg[4][2][3] = {{{0.2, 0.1, 0}, {-0.55, 0.1, 0}},
                                 {{-0.55, -0.1, 0}, {0.6, -0.1, 0}},
                                 {{0.6, 0.2, 0}, {-0.75, 0.2, 0}},
                                 {{-0.75, -0.24, 0}, {0.3, -0.24, 0}}};
    /* U-turn k joins leg k to leg k + 1: centre, radius, first angle */
    const double turn[3][4] = {{-0.55, 0.0, 0.1, M_PI / 2},
                               {0.6, 0.05, 0.15, -M_PI / 2},
                               {-0.75, -0.02, 0.22, M_PI / 2}};
    int ci = 0;
    for (int k = 0; k < 4; k++) {
        set_line(c, ci++, leg[k][0], leg[k][1]);
        if (k < 3) {
            add_pieces(c, ci, 2, turn[k][3], turn[k][3] + M_PI, circle_curve, turn[k], 1.0);
            ci += 2;
        }
    }
    const double tilt = 40 * M_PI / 180, turn_z = 30 * M_PI / 180;
    for (int j = 0; j < 4 * c->n; j++) { /* a rotation maps a Bezier curve's control points */
        double *q = c->P + 3 * j;
        double y = cos(tilt) * q[1] - sin(tilt) * q[2], z = sin(tilt) * q[1] + cos(tilt) * q[2];
        double x = cos(turn_z) * q[0] - sin(turn_z) * y;
        q[1] = sin(turn_z) * q[0] + cos(turn_z) * y;
        q[0] = x;
        q[2] = z;
    }
    c->thickness = 0.025;
    const float colour[3] = {0.8f, 0.8f, 0.82f};
    memcpy(obj->colour, colour, sizeof colour);
    return WS_OK;
}

/* Moves the curves so that the centre of their bounding box (over dense
 * samples) is OBJECT_CENTER. */
static void center_curves(ws_synth_object *obj) {
    ws_curves *c = &obj->curves;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k <= 256; k++) {
            double p[3];
            ws_curve_point(c, ci, k / 256.0, p);
            for (int x = 0; x < 3; x++) {
                lo[x] = fmin(lo[x], p[x]);
                hi[x] = fmax(hi[x], p[x]);
            }
        }
    for (int x = 0; x < 3; x++) {
        double shift = OBJECT_CENTER[x] - 0.5 * (lo[x] + hi[x]);
        for (int j = 0; j < c->n * 4; j++) c->P[j * 3 + x] += shift;
        obj->center[x] = OBJECT_CENTER[x];
    }
}

/* Capsules along each curve: about one per tube radius of arc length. */
static int build_capsules(ws_synth_object *obj, ws_status *st) {
    const ws_curves *c = &obj->curves;
    int *segments = ws_malloc(sizeof *segments * (c->n ? c->n : 1), "capsule counts", st);
    if (!segments) return st->code;
    int total = 0;
    for (int ci = 0; ci < c->n; ci++) {
        double L = 0, prev[3], p[3];
        ws_curve_point(c, ci, 0.0, prev);
        for (int k = 1; k <= 64; k++) {
            ws_curve_point(c, ci, k / 64.0, p);
            L += sqrt((p[0] - prev[0]) * (p[0] - prev[0]) + (p[1] - prev[1]) * (p[1] - prev[1]) +
                      (p[2] - prev[2]) * (p[2] - prev[2]));
            memcpy(prev, p, sizeof p);
        }
        double m = ceil(L / c->thickness);
        segments[ci] = m < MIN_CAPSULES_PER_CURVE   ? MIN_CAPSULES_PER_CURVE
                       : m > MAX_CAPSULES_PER_CURVE ? MAX_CAPSULES_PER_CURVE
                                                    : (int)m;
        total += segments[ci];
    }
    obj->capsules = ws_malloc(sizeof *obj->capsules * 6 * total, "capsules", st);
    if (!obj->capsules) {
        free(segments);
        return st->code;
    }
    double *cap = obj->capsules;
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k < segments[ci]; k++, cap += 6) {
            ws_curve_point(c, ci, (double)k / segments[ci], cap);
            ws_curve_point(c, ci, (double)(k + 1) / segments[ci], cap + 3);
        }
    obj->ncapsules = total;
    free(segments);
    return WS_OK;
}

/* The makers of the objects, in the order of synth_names. */
static int (*const makers[])(ws_synth_object *obj, ws_status *st) = {make_trefoil, make_chair,
                                                                      make_spring, make_flat};
_Static_assert(sizeof makers / sizeof makers[0] == sizeof synth_names / sizeof synth_names[0],
               "one maker per name");

/* The index of `name` in synth_names, or -1. */
static int object_index(const char *name) {
    for (int k = 0; k < synth_count; k++)
        if (!strcmp(name, synth_names[k])) return k;
    return -1;
}

int ws_synth_object_make(ws_synth_object *obj, const char *name, ws_status *st) {
    memset(obj, 0, sizeof *obj);
    int k = object_index(name);
    if (k < 0)
        return ws_fail(st, WS_EUSAGE, "%s: unknown synthetic scene (trefoil, chair, spring, flat)",
                       name);
    int rc = makers[k](obj, st);
    if (!rc) {
        center_curves(obj);
        rc = build_capsules(obj, st);
    }
    if (rc) ws_synth_object_free(obj);
    return rc;
}

void ws_synth_object_free(ws_synth_object *obj) {
    ws_curves_free(&obj->curves);
    free(obj->capsules);
    obj->capsules = NULL;
    obj->ncapsules = 0;
}

/* ---------------------------------------------------------------- rendering */

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Nearest t > 0 where the ray t D (from the origin) enters the ball of
 * centre C and radius r, or INFINITY. |t D - C|^2 = r^2 is
 * DD t^2 - 2 (D.C) t + (C.C - r^2) = 0. */
static double ray_ball(const double D[3], double DD, const double C[3], double r) {
    double b = dot3(D, C), disc = b * b - DD * (dot3(C, C) - r * r);
    if (disc < 0) return INFINITY;
    double t = (b - sqrt(disc)) / DD;
    return t > 0 ? t : INFINITY;
}

/* Nearest t > 0 where the ray t D enters the capsule of segment A -> A + len
 * axis (unit axis) and radius r, or INFINITY. The capsule is the union of a
 * finite solid cylinder and the balls at its ends; the cylinder's flat ends
 * lie inside the balls, so the first entry is the earliest of: the lateral
 * surface hit (distance r from the axis line, axial coordinate within
 * [0, len]) and the two ball hits. With w = t D - A, the lateral surface is
 * |w|^2 - (w.axis)^2 = r^2, a quadratic a t^2 + 2 b t + c = 0. */
static double ray_capsule(const double D[3], double DD, const double A[3], const double axis[3],
                          double len, const double B[3], double r) {
    double t = fmin(ray_ball(D, DD, A, r), ray_ball(D, DD, B, r));
    double Du = dot3(D, axis), Au = dot3(A, axis);
    double a = DD - Du * Du, b = -dot3(D, A) + Du * Au, c = dot3(A, A) - Au * Au - r * r;
    double disc = b * b - a * c;
    if (a > 1e-12 * DD && disc >= 0) { /* a = 0: the ray runs along the axis, balls decide */
        double tl = (-b - sqrt(disc)) / a, y = tl * Du - Au;
        if (tl > 0 && y >= 0 && y <= len && tl < t) t = tl;
    }
    return t;
}

/* Screen box (high-resolution sample indices) that contains the projection
 * of the ball (C, r), C in camera space: u = cx + f x / d over the box
 * [x - r, x + r] x [d - r, d + r], whose extremes are at its corners since
 * x / d is monotone in each of x and d (d > 0). */
static void ball_screen_box(const double C[3], double r, double f, double cx, double cy,
                            double box[4]) {
    double d = -C[2];
    for (int k = 0; k < 4; k++) {
        double x = C[0] + (k & 1 ? r : -r), y = C[1] + (k & 1 ? r : -r), dd = d + (k & 2 ? r : -r);
        double u = cx + f * x / dd, v = cy - f * y / dd;
        box[0] = fmin(box[0], u);
        box[1] = fmax(box[1], u);
        box[2] = fmin(box[2], v);
        box[3] = fmax(box[3], v);
    }
}

/* Renders the object seen by cam into img (allocated here: 3 x cam->height x
 * cam->width): the nearest tube surface of each of supersample^2 rays per
 * pixel, Lambert + ambient shaded, averaged; the background image (3 x
 * height x width, e.g. room.h's) where no tube is hit; g: NULL, or a
 * buffer of the camera's size to fill (supersample odd: line_drawing.h). */
int ws_synth_render(const ws_synth_object *obj, const ws_camera *cam, int supersample,
                    const ws_image *background, ws_image *img, ws_geometry_buffer *g, ws_status *st) {
    if (supersample < 1 || supersample > 16)
        return ws_fail(st, WS_EINTERNAL, "synth: supersampling %d is not in [1, 16]", supersample);
    if (background->width != cam->width || background->height != cam->height || background->channels != 3)
        return ws_fail(st, WS_EINTERNAL, "synth: the background is not the camera's image");
    if (g && (g->width != cam->width || g->height != cam->height || supersample % 2 == 0))
        return ws_fail(st, WS_EINTERNAL, "synth: geometry buffer %d x %d, camera %d x %d, supersampling %d", g->width,
                       g->height, cam->width, cam->height, supersample);
    const int ss = supersample, W = cam->width, H = cam->height, W2 = W * ss, H2 = H * ss;
    const double r = obj->curves.thickness;
    /* The fine grid: sample (I, J) is the centre of the fine pixel (I, J),
     * image point ((J + 1/2) / ss, (I + 1/2) / ss) (camera.h), so the
     * ss x ss samples of pixel (i, j) are centred on its centre
     * (j + 1/2, i + 1/2). In fine indices the principal point (W/2, H/2) is
     * at (W ss / 2 - 1/2, H ss / 2 - 1/2) and the focal is f ss. */
    const double f2 = cam->focal * ss, cx2 = cam->cx * ss - WS_PIXEL_CENTER,
                 cy2 = cam->cy * ss - WS_PIXEL_CENTER;
    /* the fine samples of WS_SYNTH_BAND_ROWS rows of pixels at a time */
    const size_t fine = (size_t)W2 * ss * (H < WS_SYNTH_BAND_ROWS ? H : WS_SYNTH_BAND_ROWS);
    double *depth = ws_malloc(sizeof *depth * fine, "a depth buffer", st); /* each a float's value */
    float *shade = depth ? ws_malloc(sizeof *shade * fine, "a shading buffer", st) : NULL;
    double *cc =
        shade ? ws_malloc(sizeof *cc * 6 * obj->ncapsules, "camera-space capsules", st) : NULL;
    double *axes = cc ? ws_malloc(sizeof *axes * 4 * obj->ncapsules, "capsule axes", st) : NULL;
    int *box = axes ? ws_malloc(sizeof *box * 4 * obj->ncapsules, "capsule boxes", st) : NULL;
    /* with g: each fine sample's camera-space normal */
    float *fn = box && g ? ws_malloc(sizeof *fn * 3 * fine, "a normal buffer", st) : NULL;
    if (!box || (g && !fn) || ws_image_alloc(img, W, H, 3, st)) {
        free(depth);
        free(shade);
        free(cc);
        free(axes);
        free(box);
        free(fn);
        return st->code;
    }
    for (int k = 0; k < 2 * obj->ncapsules; k++)
        ws_camera_to_cam(cam, obj->capsules + 3 * k, cc + 3 * k);
    const double light_world[3] = {0.3, -0.5, 0.8};
    double light[3]; /* unit, in camera space */
    for (int i = 0; i < 3; i++)
        light[i] = dot3(cam->R[i], light_world) / sqrt(dot3(light_world, light_world));
    /* each capsule's unit axis and length (axes[4 k ..]), and the fine
     * columns j0..j1 and rows i0..i1 it may cover (box[4 k ..]) */
    for (int k = 0; k < obj->ncapsules; k++) {
        const double *A = cc + 6 * k, *B = A + 3;
        double *axis = axes + 4 * k;
        for (int x = 0; x < 3; x++) axis[x] = B[x] - A[x];
        const double len = sqrt(dot3(axis, axis));
        for (int x = 0; x < 3; x++) axis[x] = len > 0 ? axis[x] / len : 0;
        axis[3] = len;
        double b[4] = {0, W2 - 1, 0, H2 - 1};
        if (-A[2] - r > 1e-6 && -B[2] - r > 1e-6) { /* wholly in front: a tight box */
            b[0] = b[2] = INFINITY;
            b[1] = b[3] = -INFINITY;
            ball_screen_box(A, r, f2, cx2, cy2, b);
            ball_screen_box(B, r, f2, cx2, cy2, b);
        }
        box[4 * k] = (int)fmax(0, ceil(b[0]));
        box[4 * k + 1] = (int)fmin(W2 - 1, floor(b[1]));
        box[4 * k + 2] = (int)fmax(0, ceil(b[2]));
        box[4 * k + 3] = (int)fmin(H2 - 1, floor(b[3]));
    }
    for (int top = 0; top < H; top += WS_SYNTH_BAND_ROWS) {
        const int rows = H - top < WS_SYNTH_BAND_ROWS ? H - top : WS_SYNTH_BAND_ROWS, I0 = top * ss;
        const size_t band = (size_t)rows * ss * W2;
        for (size_t k = 0; k < band; k++) depth[k] = INFINITY;
        memset(shade, 0, sizeof *shade * band);
        if (fn) memset(fn, 0, sizeof *fn * 3 * band);
        for (int k = 0; k < obj->ncapsules; k++) {
            const double *A = cc + 6 * k, *B = A + 3, *axis = axes + 4 * k, len = axis[3];
            const int j0 = box[4 * k], j1 = box[4 * k + 1];
            const int i0 = box[4 * k + 2] > I0 ? box[4 * k + 2] : I0;
            const int i1 = box[4 * k + 3] < I0 + rows * ss - 1 ? box[4 * k + 3] : I0 + rows * ss - 1;
            for (int I = i0; I <= i1; I++)
                for (int J = j0; J <= j1; J++) {
                    double D[3] = {(J - cx2) / f2, -(I - cy2) / f2, -1.0}; /* depth along D is t */
                    double DD = dot3(D, D);
                    double t = ray_capsule(D, DD, A, axis, len, B, r);
                    size_t at = (size_t)(I - I0) * W2 + J;
                    if (!(t < depth[at])) continue;
                    depth[at] = (float)t;
                    /* normal: from the nearest axis point to the hit point */
                    double P[3] = {t * D[0], t * D[1], t * D[2]}, y = 0, n[3];
                    for (int x = 0; x < 3; x++) y += (P[x] - A[x]) * axis[x];
                    y = fmin(fmax(y, 0), len);
                    for (int x = 0; x < 3; x++) n[x] = P[x] - (A[x] + y * axis[x]);
                    double nl = sqrt(dot3(n, n));
                    double lambert = nl > 0 ? fmax(0, dot3(n, light) / nl) : 0;
                    shade[at] = (float)(AMBIENT + (1 - AMBIENT) * lambert);
                    for (int x = 0; fn && nl > 0 && x < 3; x++) fn[3 * at + x] = (float)(n[x] / nl);
                }
        }
        ws_synth_resolve_rows(depth, shade, fn, ss, top, rows, obj->colour, background, cam, img, g);
    }
    free(depth);
    free(shade);
    free(cc);
    free(axes);
    free(box);
    free(fn);
    return WS_OK;
}

/* ---------------------------------------------------------------- cameras */

/* Camera-to-world of a camera at `pos` looking at `target`, world z up:
 * the camera's -z points at the target, its x is horizontal. */
static void look_at(const double pos[3], const double target[3], double c2w[4][4]) {
    double z[3], x[3], y[3];
    for (int i = 0; i < 3; i++) z[i] = pos[i] - target[i];
    double zl = sqrt(dot3(z, z));
    for (int i = 0; i < 3; i++) z[i] /= zl;
    double xl = sqrt(z[0] * z[0] + z[1] * z[1]); /* x = up x z, up = (0, 0, 1) */
    x[0] = -z[1] / xl;
    x[1] = z[0] / xl;
    x[2] = 0;
    y[0] = z[1] * x[2] - z[2] * x[1];
    y[1] = z[2] * x[0] - z[0] * x[2];
    y[2] = z[0] * x[1] - z[1] * x[0];
    memset(c2w, 0, 16 * sizeof(double));
    for (int i = 0; i < 3; i++) {
        c2w[i][0] = x[i];
        c2w[i][1] = y[i];
        c2w[i][2] = z[i];
        c2w[i][3] = pos[i];
    }
    c2w[3][3] = 1;
}

/* A camera on the sphere of CAMERA_DISTANCE around center at height
 * fraction h = cos(polar angle) in (0, 1) and azimuth phi. h stays below 1
 * (never straight above) so that "world z up" defines the camera's roll. */
static void sphere_camera(const double center[3], double h, double phi, double c2w[4][4]) {
    double ring = sqrt(1 - h * h);
    double pos[3] = {center[0] + CAMERA_DISTANCE * ring * cos(phi),
                     center[1] + CAMERA_DISTANCE * ring * sin(phi),
                     center[2] + CAMERA_DISTANCE * h};
    look_at(pos, center, c2w);
}

/* Train: a Fibonacci spiral over the upper hemisphere (equal areas: h
 * uniform, azimuth stepping by the golden angle), turned by a random
 * azimuth. Val, test: uniform random points of the hemisphere with h in
 * [0.05, 0.95]. Draws are in split order from one seeded generator. */
static void place_cameras(const double center[3], const ws_synth_options *opt,
                          double (*c2w)[4][4]) {
    ws_rng rng;
    ws_rng_seed(&rng, opt->seed);
    const double golden = M_PI * (3 - sqrt(5.0)), phi0 = 2 * M_PI * ws_rng_uniform(&rng);
    int v = 0;
    for (int k = 0; k < opt->views[WS_TRAIN]; k++, v++)
        sphere_camera(center, 1 - (k + 0.5) / opt->views[WS_TRAIN], phi0 + golden * k, c2w[v]);
    for (int s = WS_VAL; s < WS_NSPLITS; s++)
        for (int k = 0; k < opt->views[s]; k++, v++) {
            double h = 0.05 + 0.9 * ws_rng_uniform(&rng);
            sphere_camera(center, h, 2 * M_PI * ws_rng_uniform(&rng), c2w[v]);
        }
}

/* ---------------------------------------------------------------- files */

static int write_text_file(const char *path, const char *text, ws_status *st) {
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) return st->code;
    fputs(text, f.fp);
    return ws_outfile_commit(&f, st);
}

/* The n views of splits `first` .. `last` as transforms frames: file_path
 * (view_file's name; without its extension in a NeRF-synthetic split
 * file, which names its images so), mask_path where there are masks, and
 * the camera. paths holds n file and mask paths. */
static void view_frames(const ws_synth_options *opt, int first, int last, double (*c2w)[4][4],
                        ws_transforms_frame *frames, char (*paths)[2][64]) {
    for (int s = first, v = 0; s <= last; s++)
        for (int k = 0; k < opt->views[s]; k++, v++) {
            if (opt->nerfstudio)
                view_file(opt, s, k, paths[v][0], sizeof paths[v][0]);
            else
                snprintf(paths[v][0], sizeof paths[v][0], "%s/r_%d", ws_split_names[s], k);
            mask_file(opt, s, k, paths[v][1], sizeof paths[v][1]);
            frames[v] = (ws_transforms_frame){paths[v][0], opt->masks ? paths[v][1] : NULL, NULL, {{0}}, s};
            memcpy(frames[v].c2w, c2w[v], sizeof frames[v].c2w);
        }
}

/* The object's sparse points (COLMAP's points3D, nerfstudio's
 * sparse_pc.ply): SPARSE_POINTS in all, along the
 * curves (uniform in each curve's parameter) with Gaussian noise, and a
 * fraction of outliers in a box around them; seeded by opt->seed. */
static void sparse_points(const ws_curves *curves, const ws_synth_options *opt, double *points,
                          int n) {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < 4 * curves->n; k++)
        for (int i = 0; i < 3; i++) {
            lo[i] = fmin(lo[i], curves->P[3 * k + i]);
            hi[i] = fmax(hi[i], curves->P[3 * k + i]);
        }
    const double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    ws_rng rng;
    ws_rng_seed(&rng, opt->seed + 1);
    const int outliers = (int)(SPARSE_OUTLIERS * n);
    for (int k = 0; k < n; k++) {
        double *p = points + 3 * k;
        if (k < outliers) {
            for (int i = 0; i < 3; i++)
                p[i] = 0.5 * (lo[i] + hi[i]) + 1.5 * size * (2 * ws_rng_uniform(&rng) - 1);
            continue;
        }
        ws_curve_point(curves, (int)ws_rng_below(&rng, (uint64_t)curves->n), ws_rng_uniform(&rng), p);
        for (int i = 0; i < 3; i++) p[i] += SPARSE_NOISE * size * ws_rng_normal(&rng);
    }
}

/* The camera files of a NeRF-synthetic or nerfstudio scene (io/transforms.h):
 * transforms_SPLIT.json of each split that has views, or one
 * transforms.json with the intrinsics and lens and, as ns-process-data
 * writes them, the object's sparse points (sparse_pc.ply, COLMAP's). */
static int write_transforms(const char *dir, const ws_synth_options *opt, const double center[3],
                            double (*c2w)[4][4], int total, const ws_curves *curves, ws_status *st) {
    char path[WS_PATH_MAX];
    ws_transforms_frame *frames = ws_malloc(sizeof *frames * total, "transforms frames", st);
    char(*paths)[2][64] = frames ? ws_malloc(sizeof *paths * total, "transforms frames", st) : NULL;
    int rc = paths ? WS_OK : st->code;
    ws_camera cam;
    ws_lens lens;
    if (!rc && opt->nerfstudio) {
        snprintf(path, sizeof path, "%s/" WS_TRANSFORMS_FILE, dir);
        view_frames(opt, WS_TRAIN, WS_TEST, c2w, frames, paths);
        char ply[WS_PATH_MAX];
        snprintf(ply, sizeof ply, "%s/" SPARSE_PLY, dir);
        double *points = ws_malloc(sizeof *points * 3 * SPARSE_POINTS, ply, st);
        if (!points) rc = st->code;
        if (!rc) {
            sparse_points(curves, opt, points, SPARSE_POINTS);
            rc = ws_pointcloud_save_ply(ply, points, SPARSE_POINTS, st);
        }
        free(points);
        if (!rc && !(rc = synth_camera(opt, c2w[0], path, &cam, st)) && !(rc = synth_lens(opt, &cam, &lens, st))) {
            const ws_transforms_camera intrinsics = {cam.focal, cam.focal, cam.cx, cam.cy, cam.width, cam.height, lens};
            rc = ws_transforms_write_nerfstudio(path, &intrinsics, SPARSE_PLY, frames, total, st);
        }
    }
    for (int s = 0, first = 0; s < WS_NSPLITS && !rc && !opt->nerfstudio; first += opt->views[s++]) {
        if (!opt->views[s]) continue;
        snprintf(path, sizeof path, "%s/%s", dir, ws_transforms_split_files[s]);
        view_frames(opt, s, s, c2w + first, frames, paths);
        rc = ws_transforms_write_split(path, opt->angle, center, frames, opt->views[s], st);
    }
    free(frames);
    free(paths);
    return rc;
}

/* SCENE/sparse/0 (one camera, every view, the sparse points) and
 * SCENE/SPLIT_list.txt. */
static int write_colmap(const char *dir, const ws_synth_options *opt, double (*c2w)[4][4],
                        const ws_curves *curves, ws_status *st) {
    const int total = opt->views[WS_TRAIN] + opt->views[WS_VAL] + opt->views[WS_TEST];
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/sparse/0", dir);
    ws_colmap_camera camera = {.id = 1};
    ws_camera cam;
    ws_colmap_model m = {1, total, SPARSE_POINTS, &camera, NULL, NULL};
    if (synth_camera(opt, c2w[0], path, &cam, st) || synth_lens(opt, &cam, &camera.lens, st))
        return st->code;
    m.images = ws_calloc(total, sizeof *m.images, path, st);
    m.points = m.images ? ws_malloc(sizeof *m.points * 3 * SPARSE_POINTS, path, st) : NULL;
    int rc = m.points ? WS_OK : st->code;
    const char **names = rc ? NULL : ws_malloc(sizeof *names * total, path, st);
    int *split_of = names ? ws_malloc(sizeof *split_of * total, path, st) : NULL;
    if (!rc && !split_of) rc = st->code;
    for (int s = 0, v = 0; s < WS_NSPLITS && !rc; s++)
        for (int k = 0; k < opt->views[s]; k++, v++) {
            char file[64];
            view_file(opt, s, k, file, sizeof file);
            ws_colmap_image *im = &m.images[v];
            im->id = v + 1;
            im->camera_id = 1;
            snprintf(im->name, sizeof im->name, "%s", file + strlen("images/"));
            ws_colmap_from_c2w(c2w[v], im->q, im->t);
            names[v] = im->name;
            split_of[v] = s;
        }
    if (!rc) rc = ws_colmap_lists_write(dir, names, split_of, total, st);
    free(names);
    free(split_of);
    if (!rc) {
        sparse_points(curves, opt, m.points, SPARSE_POINTS);
        snprintf(path, sizeof path, "%s/sparse/0", dir);
        rc = ws_colmap_write(&m, path, opt->colmap == 1, st);
    }
    free(m.images);
    free(m.points);
    return rc;
}

static int check_options(const ws_synth_options *opt, ws_status *st) {
    static const char *const option[WS_NSPLITS] = {"--views-train", "--views-val", "--views-test"};
    for (int s = 0; s < WS_NSPLITS; s++)
        if (opt->views[s] < (s == WS_TRAIN) || opt->views[s] > 100000)
            return ws_fail(st, WS_EUSAGE, "%s: %d is not in [%d, 100000]", option[s], opt->views[s],
                           s == WS_TRAIN);
    if (opt->size < 8 || opt->size > 4096)
        return ws_fail(st, WS_EUSAGE, "--size: %d is not in [8, 4096]", opt->size);
    if ((opt->width && (opt->width < 8 || opt->width > 4096)) ||
        (opt->height && (opt->height < 8 || opt->height > 4096)))
        return ws_fail(st, WS_EUSAGE, "--width x --height: %d x %d is not in [8, 4096]", opt->width,
                       opt->height);
    const int nerf = !opt->nerfstudio && !opt->colmap;
    if (nerf && (opt->jpeg || opt->lens[0] || opt->lens[1] || opt->lens[2] || opt->lens[3]))
        return ws_fail(st, WS_EUSAGE, "%s: a NeRF-synthetic scene has PNG images and no lens "
                       "(--layout nerfstudio or colmap)", opt->jpeg ? "--jpeg" : "--lens");
    if (nerf && (opt->width || opt->height) && opt->width != opt->height)
        return ws_fail(st, WS_EUSAGE,
                       "--width %d --height %d: a NeRF-synthetic scene is square (--layout nerfstudio "
                       "or colmap take other shapes)",
                       opt->width, opt->height);
    int w, h;
    image_size(opt, &w, &h);
    if (!(fabs(opt->principal[0]) < 0.5 * w && fabs(opt->principal[1]) < 0.5 * h))
        return ws_fail(st, WS_EUSAGE, "--principal %g,%g: not inside the %d x %d image (offsets from its centre)",
                       opt->principal[0], opt->principal[1], w, h);
    if (nerf && (opt->principal[0] || opt->principal[1]))
        return ws_fail(st, WS_EUSAGE,
                       "--principal %g,%g: a NeRF-synthetic scene has its principal point at the centre "
                       "(--layout nerfstudio or colmap takes others)",
                       opt->principal[0], opt->principal[1]);
    return WS_OK;
}

/* What a scene shows: tubes, a solid or a smooth object (the others NULL). */
typedef struct {
    const ws_synth_object *tubes;
    const ws_solid *solid;
    const ws_smooth *smooth;
    double floor_z; /* the room's floor (room.h) */
} scene_object;

/* The height of the room's floor: WS_ROOM_FLOOR below the centre, or with
 * opt->on_floor the object's lowest point (a solid's lowest corner, a wire
 * object's lowest curve point less its tube radius). */
static double room_floor(const ws_synth_options *opt, const ws_solid *solid, const ws_synth_object *tubes,
                         const double center[3]) {
    if (!opt->on_floor) return center[2] - WS_ROOM_FLOOR;
    double lowest = INFINITY;
    if (solid) {
        for (int k = 0; k < 9 * solid->ntri; k += 3) lowest = fmin(lowest, solid->corner[k + 2]);
        return lowest;
    }
    for (int ci = 0; ci < tubes->curves.n; ci++)
        for (int k = 0; k <= 256; k++) {
            double p[3];
            ws_curve_point(&tubes->curves, ci, k / 256.0, p);
            lowest = fmin(lowest, p[2]);
        }
    return lowest - tubes->curves.thickness;
}

/* The background of a view: one colour v, or the room around `center`. */
static int view_background(const ws_synth_options *opt, const ws_camera *cam, const double center[3],
                           double floor_z, float v, ws_image *img, ws_status *st) {
    if (opt->room && v < 0) return ws_room_render(cam, center, floor_z, SUPERSAMPLE, img, st);
    if (ws_image_alloc(img, cam->width, cam->height, 3, st)) return st->code;
    for (size_t k = 0; k < (size_t)3 * cam->width * cam->height; k++) img->data[k] = v;
    return WS_OK;
}

static int render_object(const scene_object *obj, const ws_camera *cam, const ws_image *background, ws_image *img,
                         ws_geometry_buffer *g, ws_status *st) {
    return obj->solid ? ws_solid_render(obj->solid, cam, SUPERSAMPLE, background, img, g, st)
                      : ws_synth_render(obj->tubes, cam, SUPERSAMPLE, background, img, g, st);
}

/* One pinhole view's photo, and with opt->masks its mask (1 x H x W: the
 * share of the pixel the object covers): rendered on black and on white,
 * the difference is the share of the background each pixel shows, and the
 * photo is the black one plus the background times it (the same pixels a
 * render over the background gives). */
static int pinhole_view(const scene_object *obj, const ws_camera *cam, const double center[3],
                        const ws_synth_options *opt, ws_image *img, ws_image *mask, ws_status *st) {
    ws_image background = {0}, white = {0};
    const float colour = opt->room ? -1.0f : (float)opt->white_background;
    int rc = view_background(opt, cam, center, obj->floor_z, opt->masks ? 0.0f : colour, &background, st) ||
             render_object(obj, cam, &background, img, NULL, st);
    if (!rc && opt->masks) {
        ws_image_free(&background);
        const size_t plane = (size_t)cam->width * cam->height;
        rc = view_background(opt, cam, center, obj->floor_z, 1.0f, &white, st) ||
             render_object(obj, cam, &white, mask, NULL, st) ||
             view_background(opt, cam, center, obj->floor_z, colour, &background, st);
        for (size_t k = 0; k < 3 * plane && !rc; k++) /* mask: white - black, the background's share */
            mask->data[k] -= img->data[k];
        for (size_t k = 0; k < 3 * plane && !rc; k++) img->data[k] += background.data[k] * mask->data[k];
        for (size_t k = 0; k < plane && !rc; k++) mask->data[k] = 1 - mask->data[k];
        mask->channels = 1;
    }
    ws_image_free(&background);
    ws_image_free(&white);
    return rc ? st->code : WS_OK;
}

/* The view of cam (and its mask), through the lens when there is one: a
 * pinhole render at LENS_OVERSAMPLE times the resolution over every ray the
 * frame sees, resampled through the lens (undistort.h; where that leaves
 * the canvas, the background's colour, or grey for the room). */
static int render_view(const scene_object *obj, const ws_camera *cam, const double center[3],
                       const ws_synth_options *opt, ws_image *img, ws_image *mask, ws_status *st) {
    ws_lens lens;
    if (synth_lens(opt, cam, &lens, st)) return st->code;
    if (ws_lens_is_pinhole(&lens)) return pinhole_view(obj, cam, center, opt, img, mask, st);
    int w, h;
    double K[4];
    ws_camera canvas;
    ws_image pinhole = {0}, pinhole_mask = {0};
    const float v = opt->room ? 0.5f : (float)opt->white_background, fill[3] = {v, v, v}, none[1] = {0};
    int rc = ws_lens_canvas(&lens, LENS_OVERSAMPLE, &w, &h, K, st) ||
             ws_camera_init_pinhole(&canvas, cam->c2w, K[0], K[2], K[3], w, h, "--lens", st) ||
             pinhole_view(obj, &canvas, center, opt, &pinhole, &pinhole_mask, st) ||
             ws_image_distort(&pinhole, K, &lens, fill, img, st) ||
             (opt->masks && ws_image_distort(&pinhole_mask, K, &lens, none, mask, st));
    ws_image_free(&pinhole);
    ws_image_free(&pinhole_mask);
    return rc ? st->code : WS_OK;
}

/* Test view k's reference lines into dir/lines/test/r_K.png and
 * r_K_parts.png (io/ref_lines.h), from its geometry buffer g. */
static int write_ref_lines(const char *dir, int k, const ws_geometry_buffer *g, ws_status *st) {
    uint8_t *part = ws_malloc((size_t)g->width * g->height, "reference lines", st);
    if (!part) return st->code;
    char lines_dir[WS_PATH_MAX], name[32];
    snprintf(lines_dir, sizeof lines_dir, "%s/lines/%s", dir, ws_split_names[WS_TEST]);
    snprintf(name, sizeof name, "r_%d", k);
    int rc = ws_line_drawing(g, part, st);
    if (!rc) rc = ws_ref_lines_write(lines_dir, name, part, g->width, g->height, st);
    free(part);
    return rc;
}

/* A view of a smooth object and, for a test view, its reference lines. */
static int render_smooth(const char *dir, const ws_smooth *s, const ws_camera *cam, int split, int k,
                         const float background[3], ws_image *img, ws_status *st) {
    if (split != WS_TEST) return ws_smooth_render(s, cam, SUPERSAMPLE, background, img, NULL, st);
    ws_geometry_buffer g;
    if (ws_geometry_buffer_alloc(&g, cam->width, cam->height, st)) return st->code;
    int rc = ws_smooth_render(s, cam, SUPERSAMPLE, background, img, &g, st);
    if (!rc) rc = write_ref_lines(dir, k, &g, st);
    ws_geometry_buffer_free(&g);
    return rc;
}

/* The reference lines of a wire object's or a solid's test view k, from
 * its exact geometry (rendered once more, for the geometry buffer alone). */
static int solid_lines(const char *dir, const scene_object *obj, const ws_camera *cam, int k, ws_status *st) {
    ws_geometry_buffer g;
    ws_image background = {0}, img = {0};
    if (ws_geometry_buffer_alloc(&g, cam->width, cam->height, st)) return st->code;
    int rc = ws_image_alloc(&background, cam->width, cam->height, 3, st);
    if (!rc) memset(background.data, 0, sizeof(float) * 3 * cam->width * cam->height);
    if (!rc) rc = render_object(obj, cam, &background, &img, &g, st);
    if (!rc) rc = write_ref_lines(dir, k, &g, st);
    ws_image_free(&background);
    ws_image_free(&img);
    ws_geometry_buffer_free(&g);
    return rc;
}

/* Whether a wire object's or a solid's scene gets reference lines: a
 * pinhole NeRF-synthetic scene, whose test views `eval` scores (a lens or
 * another layout's views are not those the renderer's pixels are). */
static int ref_lines(const ws_synth_options *opt) {
    return !opt->colmap && !opt->nerfstudio && !opt->lens[0] && !opt->lens[1] && !opt->lens[2] && !opt->lens[3];
}

/* Renders and writes every view's image, in parallel; the failure of the
 * lowest view wins. */
static int write_views(const char *dir, const scene_object *obj, const double center[3],
                       const ws_synth_options *opt, double (*c2w)[4][4], int total, ws_status *st) {
    ws_status *status = ws_malloc(sizeof *status * total, "view statuses", st);
    if (!status) return st->code;
    ws_progress_begin(opt->progress, "rendering the views", "views", total);
#pragma omp parallel for schedule(dynamic)
    for (int v = 0; v < total; v++) {
        int split = 0, k = v;
        while (k >= opt->views[split]) k -= opt->views[split++];
        ws_status *vs = &status[v];
        ws_status_clear(vs);
        char path[WS_PATH_MAX], what[WS_PATH_MAX + 64];
        char file[64];
        view_file(opt, split, k, file, sizeof file);
        snprintf(path, sizeof path, "%s/%s", dir, file);
        snprintf(what, sizeof what, "%s: camera", path);
        ws_camera cam;
        ws_image img = {0}, mask = {0};
        const float colour = (float)opt->white_background, background[3] = {colour, colour, colour};
        if (!synth_camera(opt, c2w[v], what, &cam, vs) &&
            !(obj->smooth ? render_smooth(dir, obj->smooth, &cam, split, k, background, &img, vs)
                          : render_view(obj, &cam, center, opt, &img, &mask, vs)) &&
            !(!obj->smooth && split == WS_TEST && ref_lines(opt) && solid_lines(dir, obj, &cam, k, vs)) &&
            !(opt->jpeg ? ws_image_write_jpeg(path, &img, JPEG_QUALITY, vs) : ws_png_write(path, &img, vs)) &&
            opt->masks) {
            mask_file(opt, split, k, file, sizeof file);
            snprintf(path, sizeof path, "%s/%s", dir, file);
            ws_png_write(path, &mask, vs);
        }
        ws_image_free(&img);
        ws_image_free(&mask);
        ws_progress_advance(opt->progress, 1);
    }
    ws_progress_end(opt->progress);
    int rc = WS_OK;
    for (int v = 0; v < total && !rc; v++)
        if (status[v].code) {
            *st = status[v];
            rc = st->code;
        }
    free(status);
    return rc;
}

/* A folder holds one scene. The mark, written before any other file, says
 * that a folder is (or was becoming) a scene of this command's. */
#define SCENE_MARK ".wiresketch-scene"

/* Removes the regular files of folder fd that `is_scene_file` accepts. */
static int remove_scene_files(int fd, const char *where, int (*is_scene_file)(const char *), ws_status *st) {
    DIR *d = fdopendir(fd);
    if (!d) {
        close(fd);
        return ws_fail(st, WS_EIO, "%s: %s", where, strerror(errno));
    }
    rewinddir(d); /* fd may have been read before */
    int rc = WS_OK;
    for (struct dirent *e; !rc && (e = readdir(d));) {
        struct stat sb;
        if (is_scene_file(e->d_name) && fstatat(dirfd(d), e->d_name, &sb, AT_SYMLINK_NOFOLLOW) == 0 &&
            S_ISREG(sb.st_mode) && unlinkat(dirfd(d), e->d_name, 0) != 0)
            rc = ws_fail(st, WS_EIO, "%s/%s: cannot remove the old scene's file: %s", where, e->d_name,
                         strerror(errno));
    }
    closedir(d);
    return rc;
}

static int is_top_file(const char *name) {
    static const char *const files[] = {"gt_curves.json", "gt_points.ply", "train_list.txt", "val_list.txt",
                                        "test_list.txt", SPARSE_PLY};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++)
        if (!strcmp(name, files[k])) return 1;
    for (int s = 0; s < WS_NSPLITS; s++)
        if (!strcmp(name, ws_transforms_split_files[s])) return 1;
    return !strcmp(name, WS_TRANSFORMS_FILE);
}

/* r_K.png or r_K.jpg, as view_file names a view */
static int is_view_file(const char *name) {
    if (strncmp(name, "r_", 2)) return 0;
    const char *c = name + 2;
    while (*c >= '0' && *c <= '9') c++;
    return c > name + 2 && (!strcmp(c, ".png") || !strcmp(c, ".jpg"));
}

/* r_K.png and r_K_parts.png, a test view's reference lines (io/ref_lines.h) */
static int is_lines_file(const char *name) {
    if (strncmp(name, "r_", 2)) return 0;
    const char *c = name + 2;
    while (*c >= '0' && *c <= '9') c++;
    return c > name + 2 && (!strcmp(c, ".png") || !strcmp(c, "_parts.png"));
}

/* the COLMAP model's files (io/colmap.h), text or binary */
static int is_model_file(const char *name) {
    static const char *const files[] = {"cameras.txt", "images.txt", "points3D.txt",
                                        "cameras.bin", "images.bin", "points3D.bin"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++)
        if (!strcmp(name, files[k])) return 1;
    return 0;
}

/* Removes the files `is_scene_file` accepts from DIR/A/B (each folder
 * entered without following links), then B unless something else is there. */
static int clear_subfolder(int fd, const char *dir, const char *a, const char *b, int (*is_scene_file)(const char *),
                           ws_status *st) {
    int afd = openat(fd, a, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (afd < 0) return WS_OK;
    int bfd = openat(afd, b, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC), rc = WS_OK;
    if (bfd >= 0) {
        char where[WS_PATH_MAX];
        snprintf(where, sizeof where, "%s/%s/%s", dir, a, b);
        if (!(rc = remove_scene_files(bfd, where, is_scene_file, st))) unlinkat(afd, b, AT_REMOVEDIR);
    }
    close(afd);
    return rc;
}

/* `scene --out DIR` writes into a new or empty folder, or over a scene it
 * wrote before (DIR/.wiresketch-scene), whose files it first removes so
 * that none of the old scene (the transforms_val.json of one that had a
 * val split) stays beside the new one; other files there are left alone.
 * Any other folder is refused: what it holds may be a user's. Folders are
 * entered without following links, so nothing outside DIR is removed. */
static int clear_old_scene(const char *dir, ws_status *st) {
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return WS_OK; /* new, or not a folder: ws_mkdir says which */
    DIR *d = fdopendir(dup(fd));
    int empty = 1, marked = 0;
    for (struct dirent *e; d && (e = readdir(d));) {
        empty &= !strcmp(e->d_name, ".") || !strcmp(e->d_name, "..");
        marked |= !strcmp(e->d_name, SCENE_MARK);
    }
    if (d) closedir(d);
    if (empty || !marked) {
        close(fd);
        return empty ? WS_OK
                     : ws_fail(st, WS_EUSAGE, "%s: not empty and not a scene written by `wiresketch scene`; "
                                              "choose a new or empty folder", dir);
    }
    int rc = remove_scene_files(dup(fd), dir, is_top_file, st);
    /* the views of either layout (rgb/ or COLMAP's images/), their masks, and the model */
    static const char *const folders[3] = {"rgb", "images", "masks"};
    for (int f = 0; f < 3 && !rc; f++)
        for (int s = 0; s < WS_NSPLITS && !rc; s++)
            rc = clear_subfolder(fd, dir, folders[f], ws_split_names[s], is_view_file, st);
    if (!rc) rc = clear_subfolder(fd, dir, "sparse", "0", is_model_file, st);
    if (!rc) rc = clear_subfolder(fd, dir, "lines", "test", is_lines_file, st);
    static const char *const parents[5] = {"rgb", "images", "masks", "sparse", "lines"};
    for (int f = 0; f < 5 && !rc; f++) unlinkat(fd, parents[f], AT_REMOVEDIR); /* unless something else is there */
    close(fd);
    return rc;
}

int ws_synth_write(const char *name, const char *dir, const ws_synth_options *opt, ws_status *st) {
    if (check_options(opt, st)) return st->code;
    if (strlen(dir) > 4000) return ws_fail(st, WS_EUSAGE, "%s: path too long", dir);
    int solid = ws_solid_exists(name), smooth = ws_smooth_exists(name);
    if (!solid && !smooth && object_index(name) < 0)
        return ws_fail(st, WS_EUSAGE,
                       "%s: unknown synthetic scene (trefoil, chair, spring, flat, cube, "
                       "dodecahedron, nut, bracket, torus, vase, animal)",
                       name);
    /* a smooth object is drawn by sphere tracing with its reference lines, through a pinhole, and has
     * no curves to scatter a sparse cloud along */
    if (smooth && (opt->colmap || opt->lens[0] || opt->lens[1] || opt->lens[2] || opt->lens[3]))
        return ws_fail(st, WS_EUSAGE, "%s: --lens and --layout colmap are for the wire objects and solids", name);
    if (smooth && (opt->room || opt->masks))
        return ws_fail(st, WS_EUSAGE, "%s: --background room or floor and --masks are for the wire objects and solids",
                       name);
    ws_synth_object obj = {0};
    ws_solid sol = {0};
    ws_smooth smo = {0};
    if (smooth ? ws_smooth_make(&smo, name, OBJECT_CENTER, st)
        : solid ? ws_solid_make(&sol, name, OBJECT_CENTER, st)
                : ws_synth_object_make(&obj, name, st))
        return st->code;
    const double *center = smooth ? smo.center : solid ? sol.center : obj.center;
    const scene_object what = {solid || smooth ? NULL : &obj, solid ? &sol : NULL, smooth ? &smo : NULL,
                               smooth ? 0 : room_floor(opt, solid ? &sol : NULL, &obj, center)};
    char path[WS_PATH_MAX];
    int total = opt->views[WS_TRAIN] + opt->views[WS_VAL] + opt->views[WS_TEST];
    double(*c2w)[4][4] = ws_malloc(sizeof *c2w * total, "camera matrices", st);
    int rc = c2w ? WS_OK : st->code;
    const char *images = opt->colmap ? "images" : "rgb";
    snprintf(path, sizeof path, "%s/" SCENE_MARK, dir);
    if (!rc && !(rc = clear_old_scene(dir, st)) && !(rc = ws_mkdir(dir, st)))
        rc = write_text_file(path, "a scene written by `wiresketch scene`\n", st);
    snprintf(path, sizeof path, "%s/%s", dir, images);
    if (!rc) rc = ws_mkdir_inside(path, st);
    for (int s = 0; s < WS_NSPLITS && !rc; s++) {
        snprintf(path, sizeof path, "%s/%s/%s", dir, images, ws_split_names[s]);
        if (opt->views[s]) rc = ws_mkdir_inside(path, st);
    }
    snprintf(path, sizeof path, "%s/masks", dir);
    if (!rc && opt->masks) rc = ws_mkdir_inside(path, st);
    for (int s = 0; s < WS_NSPLITS && !rc && opt->masks; s++) {
        snprintf(path, sizeof path, "%s/masks/%s", dir, ws_split_names[s]);
        if (opt->views[s]) rc = ws_mkdir_inside(path, st);
    }
    snprintf(path, sizeof path, "%s/sparse", dir);
    if (!rc && opt->colmap && !(rc = ws_mkdir(path, st))) {
        snprintf(path, sizeof path, "%s/sparse/0", dir);
        rc = ws_mkdir(path, st);
    }
    snprintf(path, sizeof path, "%s/lines", dir);
    if (!rc && (smooth || ref_lines(opt)) && opt->views[WS_TEST] && !(rc = ws_mkdir(path, st))) {
        snprintf(path, sizeof path, "%s/lines/test", dir);
        rc = ws_mkdir(path, st);
    }
    if (!rc) {
        place_cameras(center, opt, c2w);
        rc = write_views(dir, &what, center, opt, c2w, total, st);
    }
    const ws_curves *gt = solid ? &sol.edges : &obj.curves;
    if (!rc) rc = opt->colmap ? write_colmap(dir, opt, c2w, gt, st) : write_transforms(dir, opt, center, c2w, total, gt, st);
    snprintf(path, sizeof path, "%s/gt_curves.json", dir);
    if (!rc && !smooth) rc = ws_curves_save(path, gt, st);
    snprintf(path, sizeof path, "%s/gt_points.ply", dir);
    if (!rc && solid) rc = ws_solid_write_points(&sol, path, GT_POINTS, opt->seed, st);
    free(c2w);
    ws_synth_object_free(&obj);
    ws_solid_free(&sol);
    return rc;
}
