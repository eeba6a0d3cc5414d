/* solids.c: solid objects with sharp edges, rendered by ray casting a
 * triangle mesh (see solids.h).
 *
 * Each triangle is rasterised over its own screen bounding box with a depth
 * buffer, so the cost follows the pixels it covers. Rays come from
 * ws_camera_pixel_ray, so the renders follow the camera module's pixel
 * convention; the boxes are padded by a pixel so that they hold whatever
 * that convention is. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "io/pointcloud.h"
#include "nn/base/rng.h"
#include "synth/solids.h"

#define AMBIENT 0.15
#define KEY 0.55
#define FILL 0.35
/* The most triangles and curves any solid here needs. */
#define MAX_TRIANGLES 1024
#define MAX_EDGES 64
/* segments of the nut's hole: a multiple of 6, so that the hexagon's corners
 * are among the directions the annulus is cut along */
#define HOLE_SEGMENTS 96
#define EDGE_THICKNESS 0.01

static const char *const solid_names[] = {"cube", "dodecahedron", "nut", "bracket"};
static const int solid_count = sizeof solid_names / sizeof solid_names[0];

int ws_solid_exists(const char *name) {
    for (int k = 0; k < solid_count; k++)
        if (!strcmp(name, solid_names[k])) return 1;
    return 0;
}

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize3(double v[3]) {
    double l = sqrt(dot3(v, v));
    for (int x = 0; x < 3; x++) v[x] /= l;
}

/* ---------------------------------------------------------------- building */

static void add_triangle(ws_solid *s, const double *a, const double *b, const double *c,
                         const double *na, const double *nb, const double *nc) {
    const double *p[3] = {a, b, c}, *n[3] = {na, nb, nc};
    for (int k = 0; k < 3; k++) {
        memcpy(s->corner + (size_t)(s->ntri * 3 + k) * 3, p[k], 3 * sizeof(double));
        memcpy(s->normal + (size_t)(s->ntri * 3 + k) * 3, n[k], 3 * sizeof(double));
    }
    s->ntri++;
}

/* A flat convex polygon (n corners in order) as a fan of triangles. */
static void add_polygon(ws_solid *s, const double (*p)[3], int n, const double normal[3]) {
    for (int k = 1; k + 1 < n; k++) add_triangle(s, p[0], p[k], p[k + 1], normal, normal, normal);
}

/* The straight edge a -> b: control points at 0, 1/3, 2/3, 1. */
static void add_line(ws_solid *s, const double a[3], const double b[3]) {
    double *P = s->edges.P + (size_t)s->edges.n++ * WS_CURVE_FLOATS;
    for (int j = 0; j < 4; j++)
        for (int x = 0; x < 3; x++) P[j * 3 + x] = a[x] + (b[x] - a[x]) * j / 3.0;
}

/* The circle of centre c and radius r in the plane z = c[2]: 4 quarter arcs. */
static void add_circle(ws_solid *s, const double c[3], double r) {
    const double kappa = 4.0 / 3.0 * (sqrt(2.0) - 1.0);
    for (int q = 0; q < 4; q++) {
        double a0 = q * M_PI / 2, a1 = a0 + M_PI / 2;
        double *P = s->edges.P + (size_t)s->edges.n++ * WS_CURVE_FLOATS;
        double pts[4][2] = {{cos(a0), sin(a0)},
                            {cos(a0) - kappa * sin(a0), sin(a0) + kappa * cos(a0)},
                            {cos(a1) + kappa * sin(a1), sin(a1) - kappa * cos(a1)},
                            {cos(a1), sin(a1)}};
        for (int j = 0; j < 4; j++) {
            P[j * 3 + 0] = c[0] + r * pts[j][0];
            P[j * 3 + 1] = c[1] + r * pts[j][1];
            P[j * 3 + 2] = c[2];
        }
    }
}

static void make_cube(ws_solid *s) {
    const double h = 0.55;
    double v[8][3];
    for (int k = 0; k < 8; k++) {
        v[k][0] = k & 1 ? h : -h;
        v[k][1] = k & 2 ? h : -h;
        v[k][2] = k & 4 ? h : -h;
    }
    /* the faces, each as 4 corners in order around it, with their normals */
    static const int face[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                   {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    static const double normal[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0},
                                        {0, 1, 0},  {-1, 0, 0}, {1, 0, 0}};
    for (int f = 0; f < 6; f++) {
        double p[4][3];
        for (int k = 0; k < 4; k++) memcpy(p[k], v[face[f][k]], sizeof p[k]);
        add_polygon(s, (const double(*)[3])p, 4, normal[f]);
    }
    for (int a = 0; a < 8; a++)
        for (int bit = 1; bit < 8; bit <<= 1)
            if (!(a & bit)) add_line(s, v[a], v[a | bit]);
}

/* Vertices (+-1, +-1, +-1), (0, +-1/phi, +-phi) and their cyclic
 * permutations; a face is the 5 vertices farthest along one of the 12
 * icosahedron directions (0, +-phi, +-1) (cyclic); an edge joins vertices
 * 2 / phi apart. */
static void make_dodecahedron(ws_solid *s) {
    const double phi = 0.5 * (1 + sqrt(5.0)), scale = 0.85 / sqrt(3.0);
    double v[20][3];
    int n = 0;
    for (int k = 0; k < 8; k++, n++)
        for (int x = 0; x < 3; x++) v[n][x] = (k >> x & 1) ? 1 : -1;
    for (int perm = 0; perm < 3; perm++)
        for (int k = 0; k < 4; k++, n++) {
            double p[3] = {0, (k & 1) ? 1 / phi : -1 / phi, (k & 2) ? phi : -phi};
            for (int x = 0; x < 3; x++) v[n][(x + perm) % 3] = p[x];
        }
    for (int perm = 0; perm < 3; perm++)
        for (int k = 0; k < 4; k++) {
            double d0[3] = {0, (k & 1) ? phi : -phi, (k & 2) ? 1 : -1}, d[3];
            for (int x = 0; x < 3; x++) d[(x + perm) % 3] = d0[x];
            normalize3(d);
            /* the face: vertices whose projection on d is the largest */
            double best = -INFINITY;
            for (int a = 0; a < 20; a++) best = fmax(best, dot3(v[a], d));
            int idx[5], m = 0;
            for (int a = 0; a < 20 && m < 5; a++)
                if (dot3(v[a], d) > best - 1e-9) idx[m++] = a;
            /* in order of angle around d */
            double u[3], w[3], ang[5], c[3] = {0, 0, 0};
            for (int a = 0; a < 5; a++)
                for (int x = 0; x < 3; x++) c[x] += v[idx[a]][x] / 5;
            for (int x = 0; x < 3; x++) u[x] = v[idx[0]][x] - c[x];
            normalize3(u);
            cross3(d, u, w);
            for (int a = 0; a < 5; a++) {
                double r[3] = {v[idx[a]][0] - c[0], v[idx[a]][1] - c[1], v[idx[a]][2] - c[2]};
                ang[a] = atan2(dot3(r, w), dot3(r, u));
            }
            for (int a = 1; a < 5; a++)
                for (int b = a; b > 0 && ang[b] < ang[b - 1]; b--) {
                    double t = ang[b];
                    ang[b] = ang[b - 1];
                    ang[b - 1] = t;
                    int ti = idx[b];
                    idx[b] = idx[b - 1];
                    idx[b - 1] = ti;
                }
            double p[5][3];
            for (int a = 0; a < 5; a++)
                for (int x = 0; x < 3; x++) p[a][x] = scale * v[idx[a]][x];
            add_polygon(s, (const double(*)[3])p, 5, d);
        }
    for (int a = 0; a < 20; a++)
        for (int b = a + 1; b < 20; b++) {
            double d2 = 0;
            for (int x = 0; x < 3; x++) d2 += (v[a][x] - v[b][x]) * (v[a][x] - v[b][x]);
            if (fabs(sqrt(d2) - 2 / phi) < 1e-9) {
                double pa[3], pb[3];
                for (int x = 0; x < 3; x++) pa[x] = scale * v[a][x], pb[x] = scale * v[b][x];
                add_line(s, pa, pb);
            }
        }
}

/* The hexagon's boundary point in direction theta (corner radius R, a
 * corner at theta = 0). */
static double hexagon_radius(double R, double theta) {
    double side = floor(theta / (M_PI / 3));
    return R * cos(M_PI / 6) / cos(theta - (side + 0.5) * M_PI / 3);
}

static void make_nut(ws_solid *s) {
    const double R = 0.75, hole = 0.35, top = 0.25;
    const double up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
    for (int k = 0; k < HOLE_SEGMENTS; k++) {
        double t0 = 2 * M_PI * k / HOLE_SEGMENTS, t1 = 2 * M_PI * (k + 1) / HOLE_SEGMENTS;
        double r0 = hexagon_radius(R, t0), r1 = hexagon_radius(R, t1 - 1e-12);
        for (int face = 0; face < 2; face++) { /* the annulus of the top, then the bottom */
            double z = face ? -top : top;
            double q[4][3] = {{hole * cos(t0), hole * sin(t0), z},
                              {r0 * cos(t0), r0 * sin(t0), z},
                              {r1 * cos(t1), r1 * sin(t1), z},
                              {hole * cos(t1), hole * sin(t1), z}};
            add_polygon(s, (const double(*)[3])q, 4, face ? down : up);
        }
        /* the hole's wall, smooth: normals towards the axis */
        double a[3] = {hole * cos(t0), hole * sin(t0), top}, b[3] = {hole * cos(t1), hole * sin(t1), top};
        double a2[3] = {a[0], a[1], -top}, b2[3] = {b[0], b[1], -top};
        double na[3] = {-cos(t0), -sin(t0), 0}, nb[3] = {-cos(t1), -sin(t1), 0};
        add_triangle(s, a, b, b2, na, nb, nb);
        add_triangle(s, a, b2, a2, na, nb, na);
    }
    for (int m = 0; m < 6; m++) {
        double t0 = m * M_PI / 3, t1 = (m + 1) * M_PI / 3, mid = (m + 0.5) * M_PI / 3;
        double c0[3] = {R * cos(t0), R * sin(t0), top}, c1[3] = {R * cos(t1), R * sin(t1), top};
        double d0[3] = {c0[0], c0[1], -top}, d1[3] = {c1[0], c1[1], -top};
        double wall[4][3], n[3] = {cos(mid), sin(mid), 0};
        memcpy(wall[0], c0, sizeof c0);
        memcpy(wall[1], c1, sizeof c1);
        memcpy(wall[2], d1, sizeof d1);
        memcpy(wall[3], d0, sizeof d0);
        add_polygon(s, (const double(*)[3])wall, 4, n);
        add_line(s, c0, c1);
        add_line(s, d0, d1);
        add_line(s, c0, d0);
    }
    const double ctop[3] = {0, 0, top}, cbottom[3] = {0, 0, -top};
    add_circle(s, ctop, hole);
    add_circle(s, cbottom, hole);
}

/* An L-shaped angle bracket: the L below (legs 1.1 long and 0.35 thick,
 * in the x-z plane, corners counterclockwise from the outer corner)
 * extruded 0.7 along y. Its caps are each two rectangles; the inner
 * corner's edge is a concave crease. */
static void make_bracket(ws_solid *s) {
    const double L = 1.1, T = 0.35, D = 0.35; /* D: half the depth */
    const double profile[6][2] = {{0, 0}, {L, 0}, {L, T}, {T, T}, {T, L}, {0, L}};
    const double front[3] = {0, -1, 0}, back[3] = {0, 1, 0};
    const double rect[2][4][2] = {{{0, 0}, {L, 0}, {L, T}, {0, T}}, {{0, T}, {T, T}, {T, L}, {0, L}}};
    for (int cap = 0; cap < 2; cap++)
        for (int r = 0; r < 2; r++) {
            double q[4][3];
            for (int k = 0; k < 4; k++) q[k][0] = rect[r][k][0], q[k][1] = cap ? D : -D, q[k][2] = rect[r][k][1];
            add_polygon(s, (const double(*)[3])q, 4, cap ? back : front);
        }
    for (int k = 0; k < 6; k++) {
        const double *a = profile[k], *b = profile[(k + 1) % 6];
        double n[3] = {b[1] - a[1], 0, a[0] - b[0]}; /* outward: the profile turns counterclockwise */
        double side[4][3] = {{a[0], -D, a[1]}, {b[0], -D, b[1]}, {b[0], D, b[1]}, {a[0], D, a[1]}};
        normalize3(n);
        add_polygon(s, (const double(*)[3])side, 4, n);
        add_line(s, side[0], side[1]);
        add_line(s, side[3], side[2]);
        add_line(s, side[0], side[3]);
    }
}

/* Moves mesh and edges so that the mesh's bounding box is centred on c. */
static void center_solid(ws_solid *s, const double c[3]) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < s->ntri * 3; k++)
        for (int x = 0; x < 3; x++) {
            lo[x] = fmin(lo[x], s->corner[k * 3 + x]);
            hi[x] = fmax(hi[x], s->corner[k * 3 + x]);
        }
    for (int x = 0; x < 3; x++) {
        double shift = c[x] - 0.5 * (lo[x] + hi[x]);
        for (int k = 0; k < s->ntri * 3; k++) s->corner[k * 3 + x] += shift;
        for (int k = 0; k < s->edges.n * 4; k++) s->edges.P[k * 3 + x] += shift;
        s->center[x] = c[x];
    }
}

int ws_solid_make(ws_solid *s, const char *name, const double center[3], ws_status *st) {
    memset(s, 0, sizeof *s);
    if (!ws_solid_exists(name))
        return ws_fail(st, WS_EUSAGE, "%s: unknown solid", name);
    s->corner = ws_malloc(sizeof *s->corner * 9 * MAX_TRIANGLES, "a mesh", st);
    s->normal = s->corner ? ws_malloc(sizeof *s->normal * 9 * MAX_TRIANGLES, "a mesh", st) : NULL;
    if (!s->normal || ws_curves_alloc(&s->edges, MAX_EDGES, st)) {
        ws_solid_free(s);
        return st->code;
    }
    s->edges.n = 0;
    s->edges.thickness = EDGE_THICKNESS;
    if (!strcmp(name, "cube"))
        make_cube(s);
    else if (!strcmp(name, "dodecahedron"))
        make_dodecahedron(s);
    else if (!strcmp(name, "nut"))
        make_nut(s);
    else
        make_bracket(s);
    const float albedo[3] = {0.75f, 0.78f, 0.82f};
    memcpy(s->albedo, albedo, sizeof albedo);
    center_solid(s, center);
    return WS_OK;
}

void ws_solid_free(ws_solid *s) {
    ws_curves_free(&s->edges);
    free(s->corner);
    free(s->normal);
    s->corner = s->normal = NULL;
    s->ntri = 0;
}

/* ---------------------------------------------------------------- rendering */

/* Moller-Trumbore: the ray t D from the origin against the triangle
 * (A, B, C); returns t (INFINITY for a miss) and the barycentric (u, v) of B
 * and C. */
static double ray_triangle(const double D[3], const double A[3], const double B[3],
                           const double C[3], double *u, double *v) {
    double e1[3], e2[3], p[3], s[3], q[3];
    for (int x = 0; x < 3; x++) {
        e1[x] = B[x] - A[x];
        e2[x] = C[x] - A[x];
        s[x] = -A[x];
    }
    cross3(D, e2, p);
    double det = dot3(e1, p);
    if (fabs(det) < 1e-14) return INFINITY;
    *u = dot3(s, p) / det;
    if (*u < -1e-12 || *u > 1 + 1e-12) return INFINITY;
    cross3(s, e1, q);
    *v = dot3(D, q) / det;
    if (*v < -1e-12 || *u + *v > 1 + 1e-12) return INFINITY;
    double t = dot3(e2, q) / det;
    return t > 0 ? t : INFINITY;
}

int ws_solid_render(const ws_solid *s, const ws_camera *cam, int supersample,
                    const ws_image *background, ws_image *img, ws_geometry_buffer *g, ws_status *st) {
    if (supersample < 1 || supersample > 16)
        return ws_fail(st, WS_EINTERNAL, "solid: supersampling %d is not in [1, 16]", supersample);
    if (background->width != cam->width || background->height != cam->height || background->channels != 3)
        return ws_fail(st, WS_EINTERNAL, "solid: the background is not the camera's image");
    if (g && (g->width != cam->width || g->height != cam->height || supersample % 2 == 0))
        return ws_fail(st, WS_EINTERNAL, "solid: geometry buffer %d x %d, camera %d x %d, supersampling %d", g->width,
                       g->height, cam->width, cam->height, supersample);
    const int ss = supersample, W = cam->width, H = cam->height, W2 = W * ss, H2 = H * ss;
    /* the fine samples of WS_SYNTH_BAND_ROWS rows of pixels at a time */
    const size_t fine = (size_t)W2 * ss * (H < WS_SYNTH_BAND_ROWS ? H : WS_SYNTH_BAND_ROWS);
    double *depth = ws_malloc(sizeof *depth * fine, "a depth buffer", st);
    float *shade = depth ? ws_malloc(sizeof *shade * fine, "a shading buffer", st) : NULL;
    double *cc = shade ? ws_malloc(sizeof *cc * 9 * s->ntri, "camera-space triangles", st) : NULL;
    double *cn = cc ? ws_malloc(sizeof *cn * 9 * s->ntri, "camera-space normals", st) : NULL;
    int *box = cn ? ws_malloc(sizeof *box * 4 * s->ntri, "triangle boxes", st) : NULL;
    /* with g: each fine sample's camera-space normal */
    float *fn = box && g ? ws_malloc(sizeof *fn * 3 * fine, "a normal buffer", st) : NULL;
    if (!box || (g && !fn) || ws_image_alloc(img, W, H, 3, st)) {
        free(depth);
        free(shade);
        free(cc);
        free(cn);
        free(box);
        free(fn);
        return st->code;
    }
    const double zero[3] = {0, 0, 0};
    double origin[3];
    ws_camera_to_cam(cam, zero, origin);
    for (int k = 0; k < 3 * s->ntri; k++) {
        double n[3];
        ws_camera_to_cam(cam, s->corner + 3 * k, cc + 3 * k);
        ws_camera_to_cam(cam, s->normal + 3 * k, n); /* a direction: R n = (R n + t) - t */
        for (int x = 0; x < 3; x++) cn[3 * k + x] = n[x] - origin[x];
    }
    double light[3] = {0.3, -0.5, 0.8}, key[3];
    normalize3(light);
    double fill[3] = {-0.5, 0.4, 1.0}; /* camera space: from the upper left, behind the camera */
    normalize3(fill);
    for (int x = 0; x < 3; x++) key[x] = dot3(cam->R[x], light);
    /* fine sample (I, J) lies at pixel coordinates ((I + 1/2) / ss - 1/2,
     * (J + 1/2) / ss - 1/2): the ss x ss samples of pixel (i, j) spread
     * evenly around its centre; box[4 tri ..]: the fine columns j0..j1 and
     * rows i0..i1 triangle tri may cover */
    for (int tri = 0; tri < s->ntri; tri++) {
        const double *A = cc + 9 * tri, *B = A + 3, *C = A + 6;
        double b[4] = {0, W2 - 1, 0, H2 - 1};
        if (-A[2] > 1e-6 && -B[2] > 1e-6 && -C[2] > 1e-6) { /* wholly in front: a tight box */
            b[0] = b[2] = INFINITY;
            b[1] = b[3] = -INFINITY;
            for (int k = 0; k < 3; k++) {
                const double *P = A + 3 * k;
                double u, v;
                ws_camera_project(cam, P, &u, &v);
                b[0] = fmin(b[0], (u + 0.5) * ss - 0.5 - ss - 1);
                b[1] = fmax(b[1], (u + 0.5) * ss - 0.5 + ss + 1);
                b[2] = fmin(b[2], (v + 0.5) * ss - 0.5 - ss - 1);
                b[3] = fmax(b[3], (v + 0.5) * ss - 0.5 + ss + 1);
            }
        }
        box[4 * tri] = (int)fmax(0, ceil(b[0]));
        box[4 * tri + 1] = (int)fmin(W2 - 1, floor(b[1]));
        box[4 * tri + 2] = (int)fmax(0, ceil(b[2]));
        box[4 * tri + 3] = (int)fmin(H2 - 1, floor(b[3]));
    }
    for (int top = 0; top < H; top += WS_SYNTH_BAND_ROWS) {
        const int rows = H - top < WS_SYNTH_BAND_ROWS ? H - top : WS_SYNTH_BAND_ROWS, I0 = top * ss;
        const size_t band = (size_t)rows * ss * W2;
        for (size_t k = 0; k < band; k++) depth[k] = INFINITY;
        memset(shade, 0, sizeof *shade * band);
        for (int tri = 0; tri < s->ntri; tri++) {
            const double *A = cc + 9 * tri, *B = A + 3, *C = A + 6;
            const int j0 = box[4 * tri], j1 = box[4 * tri + 1];
            const int i0 = box[4 * tri + 2] > I0 ? box[4 * tri + 2] : I0;
            const int i1 = box[4 * tri + 3] < I0 + rows * ss - 1 ? box[4 * tri + 3] : I0 + rows * ss - 1;
            for (int I = i0; I <= i1; I++)
                for (int J = j0; J <= j1; J++) {
                    double D[3], u = 0, v = 0;
                    ws_camera_pixel_ray(cam, (I + 0.5) / ss - 0.5, (J + 0.5) / ss - 0.5, D);
                    double t = ray_triangle(D, A, B, C, &u, &v);
                    size_t at = (size_t)(I - I0) * W2 + J;
                    if (!(t < depth[at])) continue;
                    depth[at] = t;
                    const double *na = cn + 9 * tri, *nb = na + 3, *nc = na + 6;
                    double n[3], view[3] = {-D[0], -D[1], -D[2]};
                    for (int x = 0; x < 3; x++) n[x] = (1 - u - v) * na[x] + u * nb[x] + v * nc[x];
                    normalize3(n);
                    normalize3(view);
                    if (dot3(n, view) < 0)
                        for (int x = 0; x < 3; x++) n[x] = -n[x];
                    shade[at] = (float)(AMBIENT + KEY * fmax(0, dot3(n, key)) + FILL * fmax(0, dot3(n, fill)));
                    for (int x = 0; fn && x < 3; x++) fn[3 * at + x] = (float)n[x];
                }
        }
        ws_synth_resolve_rows(depth, shade, fn, ss, top, rows, s->albedo, background, cam, img, g);
    }
    free(depth);
    free(shade);
    free(cc);
    free(cn);
    free(box);
    free(fn);
    return WS_OK;
}

int ws_solid_write_points(const ws_solid *s, const char *path, int n, uint64_t seed,
                          ws_status *st) {
    double *cum = ws_malloc(sizeof *cum * (s->ntri + 1), "triangle areas", st);
    if (!cum) return st->code;
    cum[0] = 0;
    for (int k = 0; k < s->ntri; k++) {
        const double *A = s->corner + 9 * k, *B = A + 3, *C = A + 6;
        double e1[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]}, e2[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]}, c[3];
        cross3(e1, e2, c);
        cum[k + 1] = cum[k] + 0.5 * sqrt(dot3(c, c));
    }
    double *points = ws_malloc(sizeof *points * 3 * (size_t)n, "surface points", st);
    if (!points) {
        free(cum);
        return st->code;
    }
    ws_rng rng;
    ws_rng_seed(&rng, seed);
    for (int k = 0; k < n; k++) {
        double a = ws_rng_uniform(&rng) * cum[s->ntri];
        int lo = 0, hi = s->ntri - 1; /* the triangle whose area interval holds a */
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (cum[mid + 1] < a) lo = mid + 1; else hi = mid;
        }
        double r1 = sqrt(ws_rng_uniform(&rng)), r2 = ws_rng_uniform(&rng);
        const double *A = s->corner + 9 * lo, *B = A + 3, *C = A + 6;
        for (int x = 0; x < 3; x++) points[3 * k + x] = (1 - r1) * A[x] + r1 * (1 - r2) * B[x] + r1 * r2 * C[x];
    }
    free(cum);
    int rc = ws_pointcloud_save_ply(path, points, n, st);
    free(points);
    return rc;
}
