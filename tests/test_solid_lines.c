/* test_solid_lines.c: reference lines of the program's own solids and wire
 * objects, where the geometry is known exactly (synth/line_drawing.h from
 * the renderers' geometry buffers): the cube and the dodecahedron seen
 * from a slant, every line pixel within 1.5 px of the image of one of
 * their edges (the ground truth; a mask edge pixel's centre lies up to a
 * pixel inside the edge, and thinning moves a corner), and every visible
 * edge's image drawn (a line pixel within 1.5 px of each point of it not
 * hidden by a face), and every pixel's depth that of the nearest face
 * along its ray, across the renderer's bands of rows; the
 * trefoil's lines within its tube's image radius plus 1 px of its centre
 * curves, and those drawn along them. End to end: `scene cube` writes
 * them, `eval` at the scene's size scores the drawing, at another --size
 * says in one line that it cannot. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "io/ref_lines.h"
#include "synth/line_drawing.h"
#include "synth/solids.h"
#include "synth/synth.h"

#define N 160
#define SAMPLES 200 /* per curve */

static void camera_at(ws_camera *cam, const double p[3], const double target[3], ws_status *st) {
    double z[3] = {p[0] - target[0], p[1] - target[1], p[2] - target[2]};
    double zl = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int a = 0; a < 3; a++) z[a] /= zl;
    double xl = hypot(z[0], z[1]), x[3] = {-z[1] / xl, z[0] / xl, 0};
    double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    double c2w[4][4] = {{x[0], y[0], z[0], p[0]}, {x[1], y[1], z[1], p[1]}, {x[2], y[2], z[2], p[2]}, {0, 0, 0, 1}};
    CHECK(ws_camera_init(cam, c2w, 0.69, N, N, "camera", st) == 0, "%s", st->msg);
}

/* The curves' images as dense points (u, v, depth), SAMPLES per curve. */
static void curve_images(const ws_curves *c, const ws_camera *cam, double *uvd) {
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k < SAMPLES; k++) {
            double p[3], q[3], *o = uvd + 3 * ((size_t)ci * SAMPLES + k);
            ws_curve_point(c, ci, k / (SAMPLES - 1.0), p);
            ws_camera_to_cam(cam, p, q);
            o[2] = ws_camera_project(cam, q, &o[0], &o[1]);
        }
}

/* Checks the lines of one view: each line pixel within `near` px of a
 * curve's image; each curve point seen (its depth within `seen` of the
 * buffer's, or a thin tube's) with a line pixel within `drawn` px. */
static void check_view(const char *what, const ws_curves *c, const ws_camera *cam, const ws_geometry_buffer *g,
                       double near, double seen, double drawn) {
    ws_status st;
    static uint8_t part[N * N];
    static double uvd[3 * 64 * SAMPLES];
    CHECK(c->n <= 64, "%d curves", c->n);
    CHECK(ws_line_drawing(g, part, &st) == 0, "%s", st.msg);
    curve_images(c, cam, uvd);
    int lines = 0, far = 0, visible = 0, missed = 0;
    double worst = 0;
    for (int p = 0; p < N * N; p++) {
        if (!ws_part_is_line(part[p])) continue;
        lines++;
        double u = p % N + 0.5, v = p / N + 0.5, best = INFINITY;
        for (int k = 0; k < c->n * SAMPLES; k++) best = fmin(best, hypot(uvd[3 * k] - u, uvd[3 * k + 1] - v));
        far += best > near;
        worst = fmax(worst, best);
    }
    for (int k = 0; k < c->n * SAMPLES; k++) {
        int j = (int)floor(uvd[3 * k]), i = (int)floor(uvd[3 * k + 1]);
        if (i < 2 || j < 2 || i >= N - 2 || j >= N - 2) continue;
        if (!(uvd[3 * k + 2] <= g->depth[i * N + j] + seen)) continue; /* behind a face */
        visible++;
        int hit = 0;
        for (int di = -2; di <= 2 && !hit; di++)
            for (int dj = -2; dj <= 2 && !hit; dj++)
                hit = ws_part_is_line(part[(i + di) * N + j + dj]) &&
                      hypot(j + dj + 0.5 - uvd[3 * k], i + di + 0.5 - uvd[3 * k + 1]) <= drawn;
        missed += !hit;
    }
    CHECK(lines > 100 && far == 0, "%s: %d of %d line pixels farther than %.1f px from an edge (worst %.2f)", what, far,
          lines, near, worst);
    CHECK(visible > 1000 && missed <= visible / 100, "%s: %d of %d visible edge points without a line within %.1f px",
          what, missed, visible, drawn);
}

/* Every pixel's depth in the buffer is that of the nearest triangle along
 * the ray through the pixel's centre, found here over every triangle
 * (Moller and Trumbore's test): the renderer traces WS_SYNTH_BAND_ROWS rows
 * at a time, and N = 160 rows make ten bands. Rays within 1e-6 (in
 * barycentric terms) of a triangle's edge are left out, as either answer
 * is right there. */
static void check_depth(const char *what, const ws_solid *sol, const ws_camera *cam, const ws_geometry_buffer *g) {
    int checked = 0, wrong = 0, hits = 0;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            double D[3], best = INFINITY;
            int near_edge = 0;
            ws_camera_pixel_ray(cam, i, j, D);
            for (int t = 0; t < sol->ntri; t++) {
                double A[3], B[3], C[3], e1[3], e2[3], p[3], q[3], s0[3];
                ws_camera_to_cam(cam, sol->corner + 9 * t, A);
                ws_camera_to_cam(cam, sol->corner + 9 * t + 3, B);
                ws_camera_to_cam(cam, sol->corner + 9 * t + 6, C);
                for (int x = 0; x < 3; x++) e1[x] = B[x] - A[x], e2[x] = C[x] - A[x], s0[x] = -A[x];
                p[0] = D[1] * e2[2] - D[2] * e2[1], p[1] = D[2] * e2[0] - D[0] * e2[2], p[2] = D[0] * e2[1] - D[1] * e2[0];
                q[0] = s0[1] * e1[2] - s0[2] * e1[1], q[1] = s0[2] * e1[0] - s0[0] * e1[2], q[2] = s0[0] * e1[1] - s0[1] * e1[0];
                const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
                if (fabs(det) < 1e-12) continue;
                const double u = (s0[0] * p[0] + s0[1] * p[1] + s0[2] * p[2]) / det,
                             v = (D[0] * q[0] + D[1] * q[1] + D[2] * q[2]) / det,
                             along = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
                if (u < -1e-6 || v < -1e-6 || u + v > 1 + 1e-6 || !(along > 0)) continue;
                near_edge |= u < 1e-6 || v < 1e-6 || u + v > 1 - 1e-6;
                best = fmin(best, along);
            }
            if (near_edge) continue;
            const float got = g->depth[(size_t)i * N + j];
            checked++;
            hits += isfinite(best);
            wrong += isfinite(best) != isfinite(got) || (isfinite(best) && fabs(got - best) > 1e-5 * best);
        }
    CHECK(checked > N * N * 9 / 10 && hits > N * N / 10 && wrong == 0,
          "%s: %d of %d pixels (%d on the solid) with a depth not the nearest triangle's", what, wrong, checked, hits);
}

int main(void) {
    ws_status st;
    ws_status_clear(&st);
    const double center[3] = {0, 0, 0}, eye[3] = {2.6, -3.1, 2.2};
    ws_camera cam;
    camera_at(&cam, eye, center, &st);
    ws_geometry_buffer g;
    ws_image background, img = {0};
    CHECK(ws_geometry_buffer_alloc(&g, N, N, &st) == 0 && ws_image_alloc(&background, N, N, 3, &st) == 0, "%s",
          st.msg);
    memset(background.data, 0, sizeof(float) * 3 * N * N);
    const char *solids[2] = {"cube", "dodecahedron"};
    for (int s = 0; s < 2; s++) {
        ws_solid sol;
        CHECK(ws_solid_make(&sol, solids[s], center, &st) == 0, "%s", st.msg);
        CHECK(ws_solid_render(&sol, &cam, 3, &background, &img, &g, &st) == 0, "%s", st.msg);
        ws_image_free(&img);
        /* a visible edge point lies on the face the buffer holds: within a hair of its depth */
        check_view(solids[s], &sol.edges, &cam, &g, 1.5, 1e-3, 1.5);
        check_depth(solids[s], &sol, &cam, &g);
        ws_solid_free(&sol);
    }
    ws_synth_object knot;
    CHECK(ws_synth_object_make(&knot, "trefoil", &st) == 0, "%s", st.msg);
    camera_at(&cam, (double[3]){knot.center[0] + 2.6, knot.center[1] - 3.1, knot.center[2] + 2.2}, knot.center, &st);
    CHECK(ws_synth_render(&knot, &cam, 3, &background, &img, &g, &st) == 0, "%s", st.msg);
    ws_image_free(&img);
    /* the tube's radius in pixels at the nearest depth */
    double radius = cam.focal * knot.curves.thickness / (sqrt(2.6 * 2.6 + 3.1 * 3.1 + 2.2 * 2.2) - 1.5);
    check_view("trefoil", &knot.curves, &cam, &g, radius + 1, 2 * knot.curves.thickness, radius + 1.5);
    ws_synth_object_free(&knot);
    /* a buffer of the wrong size, an even supersampling */
    ws_solid sol;
    ws_geometry_buffer small;
    CHECK(ws_solid_make(&sol, "cube", center, &st) == 0 && ws_geometry_buffer_alloc(&small, N / 2, N, &st) == 0, "%s",
          st.msg);
    CHECK(ws_solid_render(&sol, &cam, 3, &background, &img, &small, &st) == WS_EINTERNAL &&
              !strcmp(st.msg, "solid: geometry buffer 80 x 160, camera 160 x 160, supersampling 3"),
          "%s", st.msg);
    CHECK(ws_solid_render(&sol, &cam, 2, &background, &img, &g, &st) == WS_EINTERNAL, "an even supersampling");
    ws_geometry_buffer_free(&small);
    ws_solid_free(&sol);
    ws_geometry_buffer_free(&g);
    ws_image_free(&background);
    const char *bin = program_path();
    char tmp[300], path[600];
    static char out[1 << 15];
    snprintf(tmp, sizeof tmp, "%s/cube", test_tmpdir("solid_lines"));
    int rc = run_cmd(out, sizeof out, "%s scene cube --out %s --size 48 --views-train 8 --views-val 1 --views-test 2",
                     bin, tmp);
    snprintf(path, sizeof path, "%s/lines/test/r_1_parts.png", tmp);
    CHECK(rc == 0 && access(path, R_OK) == 0, "scene cube: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s eval %s --curves %s/gt_curves.json --loss none --size 48 --threads 1", bin,
                 tmp, tmp);
    CHECK(rc == 0 && strstr(out, "\"drawing\": {\"views\": 2") && strstr(out, "\"drawing_curves\""),
          "eval at the scene's size: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, "{ %s eval %s --curves %s/gt_curves.json --loss none --size 64 --threads 1 >/dev/null; }",
                 bin, tmp, tmp);
    char want[800];
    snprintf(want, sizeof want, "wiresketch: warning: %s/lines/test: the reference lines are 48 x 48 pixels, the views "
             "64 x 64 (--size); the drawing is not scored\n", tmp);
    CHECK(rc == 0 && !strcmp(out, want), "eval at another size: %d %s", rc, out);
    return check_summary();
}
