/* export.c: OBJ, PLY and SVG files of a sketch (see export.h). */
#include <math.h>
#include <stdio.h>
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
    fprintf(f.fp, "# wiresketch: %d cubic Bezier curves as polylines of %d segments\n", c->n,
            WS_EXPORT_SEGMENTS);
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k < VERTS_PER_CURVE; k++) {
            double p[3];
            polyline_point(c, ci, k, p);
            fprintf(f.fp, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
    for (int ci = 0; ci < c->n; ci++) {
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

int ws_export_svg(const char *path, const ws_curves *c, const ws_camera *cam, ws_status *st) {
    ws_outfile f;
    if (ws_curves_check_finite(path, c, st) || ws_outfile_open(&f, path, st)) return st->code;
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
        double mid[3];
        ws_curve_point(c, ci, 0.5, mid);
        double sigma = cam->focal * c->thickness / depth(cam, mid);
        fprintf(f.fp, "<path stroke-width=\"%.4g\" d=\"", width * sigma);
        for (int k = 0; k < VERTS_PER_CURVE; k++) {
            double p[3], cc[3];
            polyline_point(c, ci, k, p);
            ws_camera_to_cam(cam, p, cc);
            double u, v; /* SVG's pixel (i, j) is [j, j+1] x [i, i+1], as the camera's */
            ws_camera_project(cam, cc, &u, &v);
            fprintf(f.fp, "%s%.3f %.3f", k ? " L" : "M", u, v);
        }
        fprintf(f.fp, "\"/>\n");
    }
    fprintf(f.fp, "</g>\n</svg>\n");
    return ws_outfile_commit(&f, st);
}
