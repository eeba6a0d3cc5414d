/* export.c: OBJ, PLY and SVG files of a sketch (see export.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "io/export.h"
#include "base/outfile.h"

#define VERTS_PER_CURVE (WS_EXPORT_SEGMENTS + 1)
#define SVG_NEAR 1e-3

/* Vertex k of curve ci's polyline. */
static void polyline_point(const ws_curves *c, int ci, int k, double p[3]) {
    ws_curve_point(c, ci, (double)k / WS_EXPORT_SEGMENTS, p);
}

int ws_export_obj(const char *path, const ws_curves *c, ws_status *st) {
    ws_outfile f;
    if (ws_curves_check_finite(path, c, st) || ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "# wiresketch: %d cubic Bezier curves as polylines of %d segments, one object each\n", c->n,
            WS_EXPORT_SEGMENTS);
    for (int ci = 0; ci < c->n; ci++) {
        fprintf(f.fp, "o curve_%d\n", ci);
        for (int k = 0; k < VERTS_PER_CURVE; k++) {
            double p[3];
            polyline_point(c, ci, k, p);
            fprintf(f.fp, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
        fputc('l', f.fp);
        for (int k = 0; k < VERTS_PER_CURVE; k++) fprintf(f.fp, " %d", ci * VERTS_PER_CURVE + k + 1);
        fputc('\n', f.fp);
    }
    return ws_outfile_commit(&f, st);
}

int ws_export_ply(const char *path, const ws_curves *c, ws_status *st) {
    ws_outfile f;
    if (ws_curves_check_finite(path, c, st) || ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp,
            "ply\nformat ascii 1.0\ncomment wiresketch: %d cubic Bezier curves as polylines\n"
            "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "element edge %d\nproperty int vertex1\nproperty int vertex2\nend_header\n",
            c->n, c->n * VERTS_PER_CURVE, c->n * WS_EXPORT_SEGMENTS);
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k < VERTS_PER_CURVE; k++) {
            double p[3];
            polyline_point(c, ci, k, p);
            fprintf(f.fp, "%.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k < WS_EXPORT_SEGMENTS; k++)
            fprintf(f.fp, "%d %d\n", ci * VERTS_PER_CURVE + k, ci * VERTS_PER_CURVE + k + 1);
    return ws_outfile_commit(&f, st);
}

/* Depth of a world point in the camera. */
static double depth(const ws_camera *cam, const double p[3]) {
    double cc[3];
    ws_camera_to_cam(cam, p, cc);
    return -cc[2];
}

/* Stroke width over sigma: where a dense line of Gaussians of footprint
 * sigma spaced s apart reaches alpha 1/2. Across the line the weights add up
 * to about k exp(-r^2 / (2 sigma^2)) with k = sqrt(2 pi) sigma / s, which is
 * sqrt(2 pi) / (2 (1 - overlap)) in any view (sigma and s = 2 thickness
 * (1 - overlap) scale alike under projection), and alpha = 1/2 where that
 * sum is ln 2. At least 2 (one sigma each side). */
static double stroke_width_in_sigmas(const ws_curves *c) {
    double k = sqrt(2 * M_PI) / (2 * (1 - c->overlap));
    double ratio = k / log(2.0);
    return ratio > exp(0.5) ? 2 * sqrt(2 * log(ratio)) : 2.0;
}

/* The image of curve ci at t: pixel (u, v) and its derivative in t. */
static void image_point(const ws_camera *cam, const double *P, double t, double uv[2], double duv[2]) {
    double s = 1 - t, p[3], dp[3], c[3], dc[3];
    for (int i = 0; i < 3; i++) {
        p[i] = s * s * s * P[i] + 3 * s * s * t * P[3 + i] + 3 * s * t * t * P[6 + i] + t * t * t * P[9 + i];
        dp[i] = 3 * (s * s * (P[3 + i] - P[i]) + 2 * s * t * (P[6 + i] - P[3 + i]) + t * t * (P[9 + i] - P[6 + i]));
    }
    ws_camera_to_cam(cam, p, c);
    for (int i = 0; i < 3; i++) dc[i] = cam->R[i][0] * dp[0] + cam->R[i][1] * dp[1] + cam->R[i][2] * dp[2];
    /* u = cx + f c0 / d, v = cy - f c1 / d with d = -c2 > SVG_NEAR (the
     * curve lies in front of the camera) */
    double d = -c[2], dd = -dc[2];
    uv[0] = cam->cx + cam->focal * c[0] / d;
    uv[1] = cam->cy - cam->focal * c[1] / d;
    duv[0] = cam->focal * (dc[0] * d - c[0] * dd) / (d * d);
    duv[1] = -cam->focal * (dc[1] * d - c[1] * dd) / (d * d);
}

/* The image of t in [t0, t1] as cubic segments " C x1 y1 x2 y2 x3 y3",
 * halved until within the tolerance (at most `depth` more times). */
static void write_segments(FILE *fp, const ws_camera *cam, const double *P, double t0, double t1, int depth) {
    double a[2], da[2], b[2], db[2], h = (t1 - t0) / 3;
    image_point(cam, P, t0, a, da);
    image_point(cam, P, t1, b, db);
    double q[4][2] = {{a[0], a[1]}, {a[0] + h * da[0], a[1] + h * da[1]}, {b[0] - h * db[0], b[1] - h * db[1]},
                      {b[0], b[1]}};
    double err = 0;
    for (int k = 1; k < 4; k++) {
        double s = k / 4.0, r = 1 - s, x[2], dx[2];
        image_point(cam, P, t0 + s * (t1 - t0), x, dx);
        for (int i = 0; i < 2; i++) {
            double bez = r * r * r * q[0][i] + 3 * r * r * s * q[1][i] + 3 * r * s * s * q[2][i] + s * s * s * q[3][i];
            err = fmax(err, fabs(bez - x[i]));
        }
    }
    if (err > WS_EXPORT_SVG_TOLERANCE && depth > 0) {
        write_segments(fp, cam, P, t0, (t0 + t1) / 2, depth - 1);
        write_segments(fp, cam, P, (t0 + t1) / 2, t1, depth - 1);
        return;
    }
    fprintf(fp, " C%.3f %.3f %.3f %.3f %.3f %.3f", q[1][0], q[1][1], q[2][0], q[2][1], q[3][0], q[3][1]);
}

/* Whether the curve's point at t is drawn: in front of the far limit (if
 * any) and where the drawing keeps the curves (if it says), where its
 * image falls inside the frame (outside it nothing hides it). */
static int seen(const ws_camera *cam, const double *P, const float *far, const uint8_t *keep, double t) {
    double uv[2], duv[2], p[3], c[3], s = 1 - t;
    for (int i = 0; i < 3; i++)
        p[i] = s * s * s * P[i] + 3 * s * s * t * P[3 + i] + 3 * s * t * t * P[6 + i] + t * t * t * P[9 + i];
    ws_camera_to_cam(cam, p, c);
    image_point(cam, P, t, uv, duv);
    int j = (int)floor(uv[0]), i = (int)floor(uv[1]);
    if (i < 0 || j < 0 || i >= cam->height || j >= cam->width) return 1;
    size_t at = (size_t)i * cam->width + j;
    return (!far || -c[2] <= far[at]) && (!keep || keep[at]);
}

/* A line pixel next to (i, j) not yet taken (4-neighbours first, so that
 * a chain follows the line rather than cutting its corners); -1: none. */
static long next_pixel(const uint8_t *lines, const uint8_t *taken, int W, int H, int i, int j) {
    static const int di[8] = {-1, 1, 0, 0, -1, -1, 1, 1}, dj[8] = {0, 0, -1, 1, -1, 1, -1, 1};
    for (int k = 0; k < 8; k++) {
        int ii = i + di[k], jj = j + dj[k];
        if (ii < 0 || ii >= H || jj < 0 || jj >= W) continue;
        size_t q = (size_t)ii * W + jj;
        if (lines[q] && !taken[q]) return (long)q;
    }
    return -1;
}

/* The line pixels as polylines through their centres: chains of
 * 8-connected pixels, each grown from its first pixel (raster order) both
 * ways; a lone pixel is a dot (a zero-length segment, which round caps
 * draw). */
static int write_lines(FILE *fp, const uint8_t *lines, int W, int H, ws_status *st) {
    const size_t n = (size_t)W * H;
    uint8_t *taken = ws_calloc(n, 1, "SVG lines", st);
    long *chain = taken ? ws_malloc(2 * n * sizeof *chain, "SVG lines", st) : NULL;
    if (!chain) {
        free(taken);
        return st->code;
    }
    fprintf(fp, "<g id=\"hull_lines\" stroke-width=\"1\">\n");
    for (size_t p0 = 0; p0 < n; p0++) {
        if (!lines[p0] || taken[p0]) continue;
        /* chain[first .. last]: grown backwards from n, forwards from n */
        long first = (long)n, last = (long)n;
        chain[n] = (long)p0;
        taken[p0] = 1;
        for (int way = 0; way < 2; way++)
            for (long q = (long)p0; (q = next_pixel(lines, taken, W, H, (int)(q / W), (int)(q % W))) >= 0;) {
                taken[q] = 1;
                if (way) chain[--first] = q;
                else chain[++last] = q;
            }
        fprintf(fp, "<path d=\"");
        for (long k = first; k <= last; k++)
            fprintf(fp, "%s%.1f %.1f", k == first ? "M" : " L", chain[k] % W + WS_PIXEL_CENTER, chain[k] / W + WS_PIXEL_CENTER);
        fprintf(fp, "%s\"/>\n", first == last ? " l0 0" : "");
    }
    fprintf(fp, "</g>\n");
    free(taken);
    free(chain);
    return WS_OK;
}

int ws_export_svg(const char *path, const ws_curves *c, const ws_camera *cam, const float *far,
                  const ws_svg_drawing *drawing, ws_status *st) {
    ws_outfile f;
    if (ws_curves_check_finite(path, c, st) || ws_outfile_open(&f, path, st)) return st->code;
    const uint8_t *keep = drawing ? drawing->keep : NULL;
    fprintf(f.fp,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
            "viewBox=\"0 0 %d %d\">\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
            "<g fill=\"none\" stroke=\"black\" stroke-linecap=\"round\" "
            "stroke-linejoin=\"round\">\n",
            cam->width, cam->height, cam->width, cam->height);
    double width = stroke_width_in_sigmas(c);
    for (int ci = 0; ci < c->n; ci++) {
        int in_front = 1;
        const double *P = c->P + (size_t)ci * WS_CURVE_FLOATS;
        for (int j = 0; j < 4; j++) in_front &= depth(cam, P + j * 3) > SVG_NEAR;
        if (!in_front) continue;
        /* the seen runs [t0, t1]: cut halfway between samples that differ */
        double runs[WS_EXPORT_SVG_SAMPLES + 1][2];
        int nruns = 0, open = 0;
        for (int k = 0; k <= WS_EXPORT_SVG_SAMPLES; k++) {
            double t = (double)k / WS_EXPORT_SVG_SAMPLES, half = 0.5 / WS_EXPORT_SVG_SAMPLES;
            int is_seen = (!far && !keep) || seen(cam, P, far, keep, t);
            if (is_seen && !open) runs[nruns][0] = k ? t - half : 0;
            if (!is_seen && open) runs[nruns++][1] = t - half;
            open = is_seen;
        }
        if (open) runs[nruns++][1] = 1;
        if (!nruns) continue;
        double mid[3];
        ws_curve_point(c, ci, 0.5, mid);
        double sigma = cam->focal * c->thickness / depth(cam, mid);
        fprintf(f.fp, "<path id=\"curve_%d\" stroke-width=\"%.4g\" d=\"", ci, width * sigma);
        for (int r = 0; r < nruns; r++) {
            double uv[2], duv[2];
            image_point(cam, P, runs[r][0], uv, duv);
            /* SVG's pixel (i, j) is [j, j+1] x [i, i+1], as the camera's */
            fprintf(f.fp, "%sM%.3f %.3f", r ? " " : "", uv[0], uv[1]);
            write_segments(f.fp, cam, P, runs[r][0], runs[r][1], 6);
        }
        fprintf(f.fp, "\"/>\n");
    }
    if (drawing && write_lines(f.fp, drawing->lines, cam->width, cam->height, st)) {
        ws_outfile_abort(&f);
        return st->code;
    }
    fprintf(f.fp, "</g>\n</svg>\n");
    return ws_outfile_commit(&f, st);
}
