/* test_surface.c: curves start (and respawn) only where a camera sees the
 * hull's surface squarely (geometry/surface.h). The hull is a box of 6^3
 * voxels; camera A looks straight down on it, camera B at its +x side.
 * Seen by A alone, the box's top is placeable (facing 1) and its sides
 * (seen edge-on, or from behind) and bottom are not, and neither the
 * spread nor the initial curves pick a point there; with B too, the +x
 * side is placeable and picked, the others stay out; with no camera no
 * point is placeable and spreading falls back to all of them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "geometry/surface.h"

#define GRID 10

/* A camera at pos looking at the origin: its x, y axes given (z = x cross y). */
static int camera(ws_camera *cam, const double pos[3], const double x[3], const double y[3], ws_status *st) {
    double c2w[4][4] = {{0}};
    const double z[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
    for (int i = 0; i < 3; i++) {
        c2w[i][0] = x[i];
        c2w[i][1] = y[i];
        c2w[i][2] = z[i];
        c2w[i][3] = pos[i];
    }
    c2w[3][3] = 1;
    return ws_camera_init(cam, c2w, 1.0, 64, 64, "test camera", st);
}

/* Points of s whose normal is within 10 degrees of axis (a, sign). */
static int along(const ws_hull_surface *s, int i, int a, double sign) {
    return sign * s->normal[3 * i + a] > cos(10 * M_PI / 180);
}

int main(void) {
    ws_status st;
    ws_hull h = {.n = {GRID, GRID, GRID}, .origin = {-0.5, -0.5, -0.5}, .voxel = 0.1};
    h.outside = malloc(GRID * GRID * GRID);
    for (int z = 0; z < GRID; z++)
        for (int y = 0; y < GRID; y++)
            for (int x = 0; x < GRID; x++) {
                int in = x >= 2 && x < 8 && y >= 2 && y < 8 && z >= 2 && z < 8;
                h.outside[ws_hull_index(&h, x, y, z)] = !in;
                h.kept += in;
            }
    ws_camera top, side;
    const double above[3] = {0, 0, 4}, beside[3] = {4, 0, 0}, ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0},
                 ez[3] = {0, 0, 1};
    CHECK(camera(&top, above, ex, ey, &st) == WS_OK && camera(&side, beside, ey, ez, &st) == WS_OK,
          "cameras: %s", st.msg);
    const ws_hull_view views[2] = {{.cam = &top}, {.cam = &side}};

    /* A alone */
    ws_hull_surface s;
    CHECK(ws_hull_surface_make(&h, views, 1, &s, &st) == WS_OK, "surface: %s", st.msg);
    int placeable = 0, top_face = 0, top_ok = 1, hidden_ok = 1;
    for (int i = 0; i < s.n; i++) {
        placeable += s.facing[i] >= WS_SURFACE_MIN_FACING;
        if (along(&s, i, 2, 1)) {
            top_face++;
            top_ok &= s.facing[i] > 0.99;
        }
        for (int a = 0; a < 3; a++)
            for (int sign = -1; sign <= 1; sign += 2)
                if (!(a == 2 && sign == 1) && along(&s, i, a, sign)) hidden_ok &= s.facing[i] < WS_SURFACE_MIN_FACING;
    }
    CHECK(s.n == 6 * 6 * 6 - 4 * 4 * 4 && top_face == 16, "%d surface points (want 152), %d on the top face (16)",
          s.n, top_face);
    CHECK(top_ok, "the top, seen face-on, has a facing below 0.99");
    CHECK(hidden_ok, "a side or the bottom, seen edge-on or not at all, is placeable");
    CHECK(s.placeable == placeable && ws_hull_surface_candidates(&s) == placeable && placeable > top_face &&
              placeable < s.n / 2,
          "%d placeable points counted, %d with facing >= %g of %d", s.placeable, placeable, WS_SURFACE_MIN_FACING,
          s.n);
    int *picked = malloc(sizeof(int) * s.n);
    double spacing;
    ws_rng rng;
    ws_rng_seed(&rng, 3);
    CHECK(ws_hull_surface_spread(&s, NULL, 0, placeable, &rng, picked, &spacing, &st) == WS_OK, "spread: %s",
          st.msg);
    int picked_ok = 1, picked_top = 0;
    for (int m = 0; m < placeable; m++) {
        picked_ok &= s.facing[picked[m]] >= WS_SURFACE_MIN_FACING;
        picked_top += along(&s, picked[m], 2, 1);
        for (int q = 0; q < m; q++) picked_ok &= picked[q] != picked[m];
    }
    CHECK(picked_ok && picked_top == top_face, "the spread picked a point seen only edge-on (or twice)");
    CHECK(ws_hull_surface_spread(&s, NULL, 0, placeable + 1, &rng, picked, &spacing, &st) == WS_EINTERNAL,
          "more points than are placeable were spread");
    ws_curves c;
    CHECK(ws_curves_init_hull(&c, &s, 10, 0.05, 0.01, 0.6, &rng, &st) == WS_OK, "init: %s", st.msg);
    int starts_ok = 1;
    for (int ci = 0; ci < c.n; ci++) {
        double mid[3];
        ws_curve_point(&c, ci, 0.5, mid);
        starts_ok &= mid[2] > 0.2; /* the top layer's centres lie at z = 0.25 */
    }
    CHECK(starts_ok, "a curve starts below the top layer, where A sees the box only edge-on");
    ws_curves_free(&c);
    ws_hull_surface_free(&s);

    /* A and B: the +x side is seen face-on too */
    CHECK(ws_hull_surface_make(&h, views, 2, &s, &st) == WS_OK, "surface: %s", st.msg);
    int side_ok = 1, others_ok = 1;
    for (int i = 0; i < s.n; i++) {
        if (along(&s, i, 0, 1)) side_ok &= s.facing[i] > 0.99;
        if (along(&s, i, 0, -1) || along(&s, i, 1, 1) || along(&s, i, 1, -1) || along(&s, i, 2, -1))
            others_ok &= s.facing[i] < WS_SURFACE_MIN_FACING;
    }
    CHECK(side_ok && others_ok, "with B, the +x side is placeable (%d) and the other sides not (%d)", side_ok,
          others_ok);
    int k = ws_hull_surface_candidates(&s), picked_side = 0;
    CHECK(ws_hull_surface_spread(&s, NULL, 0, k, &rng, picked, &spacing, &st) == WS_OK, "spread: %s", st.msg);
    for (int m = 0; m < k; m++) picked_side += along(&s, picked[m], 0, 1);
    CHECK(picked_side == 16, "%d points of the +x side picked, want its 16", picked_side);
    ws_hull_surface_free(&s);

    /* no camera: nothing is placeable, so every point is a candidate */
    CHECK(ws_hull_surface_make(&h, views, 0, &s, &st) == WS_OK && s.placeable == 0 &&
              ws_hull_surface_candidates(&s) == s.n &&
              ws_hull_surface_spread(&s, NULL, 0, s.n, &rng, picked, &spacing, &st) == WS_OK,
          "without cameras: %d placeable, spread: %s", s.placeable, st.msg);
    ws_hull_surface_free(&s);
    free(picked);
    ws_hull_free(&h);
    return check_summary();
}
