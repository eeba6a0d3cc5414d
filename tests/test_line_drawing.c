/* test_line_drawing.c: reference lines from a geometry buffer
 * (synth/line_drawing.h) on hand-made buffers (a crease, a depth step, a
 * speck), and end to end: `wiresketch scene torus` writes test views'
 * lines that read back (io/ref_lines.h), and `eval` scores a sketch
 * against them. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "io/ref_lines.h"
#include "synth/line_drawing.h"

#define N 40

/* The square of rows and columns 10..29 at depth 4; its right half (columns
 * 20..29) at depth `right_depth` with normal (0, 0, 1), the left half with
 * normal left_normal. */
static void make_buffer(ws_geometry_buffer *g, double right_depth, const float left_normal[3]) {
    const size_t plane = (size_t)N * N;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            size_t p = (size_t)i * N + j;
            int in = i >= 10 && i < 30 && j >= 10 && j < 30;
            g->coverage[p] = in ? 1.0f : 0.0f;
            g->depth[p] = !in ? INFINITY : j >= 20 ? (float)right_depth : 4.0f;
            for (int c = 0; c < 3; c++) g->normal[c * plane + p] = !in ? 0 : j >= 20 ? (c == 2) : left_normal[c];
        }
}

/* How many pixels of kind `kind` part has, and how many of them lie outside columns j0..j1. */
static int count(const uint8_t *part, int kind, int j0, int j1, int *outside) {
    int n = 0;
    *outside = 0;
    for (int p = 0; p < N * N; p++)
        if (part[p] == kind) {
            n++;
            *outside += p % N < j0 || p % N > j1;
        }
    return n;
}

static void test_rules(void) {
    ws_status st;
    ws_status_clear(&st);
    ws_geometry_buffer g;
    static uint8_t part[N * N];
    CHECK(ws_geometry_buffer_alloc(&g, N, N, &st) == 0, "%s", st.msg);
    const float facing[3] = {0, 0, 1}, turned[3] = {1, 0, 0}, slanted[3] = {0.5f, 0, 0.8660254f};
    int off, n;
    /* a 90 degree crease down the middle: one line there, no contour */
    make_buffer(&g, 4.0, turned);
    CHECK(ws_line_drawing(&g, part, &st) == 0, "%s", st.msg);
    n = count(part, WS_PART_CREASE, 19, 20, &off);
    CHECK(n >= 16 && n <= 20 && off == 0, "crease: %d pixels, %d off the fold", n, off);
    CHECK(count(part, WS_PART_CONTOUR, 0, N, &off) == 0, "crease: no contour");
    /* the silhouette: the square's border, one pixel wide */
    n = count(part, WS_PART_SILHOUETTE, 10, 29, &off);
    CHECK(n >= 70 && n <= 76 && off == 0, "silhouette: %d pixels", n);
    /* 30 degrees: no crease */
    make_buffer(&g, 4.0, slanted);
    CHECK(ws_line_drawing(&g, part, &st) == 0 && count(part, WS_PART_CREASE, 0, N, &off) == 0, "30 degrees: crease");
    /* the right half 3% farther (the limit is 2% of the near depth): the near side's edge is a contour */
    make_buffer(&g, 4.12, facing);
    CHECK(ws_line_drawing(&g, part, &st) == 0, "%s", st.msg);
    n = count(part, WS_PART_CONTOUR, 19, 19, &off);
    CHECK(n >= 16 && n <= 18 && off == 0, "contour: %d pixels, %d off column 19", n, off);
    make_buffer(&g, 4.06, facing); /* 1.5%: none */
    CHECK(ws_line_drawing(&g, part, &st) == 0 && count(part, WS_PART_CONTOUR, 0, N, &off) == 0, "1.5%%: contour");
    /* a 2 x 2 object: its 4 outline pixels are a speck, dropped */
    for (int p = 0; p < N * N; p++) g.coverage[p] = 0;
    for (int i = 5; i < 7; i++)
        for (int j = 5; j < 7; j++) g.coverage[i * N + j] = 1;
    CHECK(ws_line_drawing(&g, part, &st) == 0 && count(part, WS_PART_MASK, 0, N, &off) == 4 &&
              count(part, WS_PART_SILHOUETTE, 0, N, &off) == 0,
          "speck kept");
    ws_geometry_buffer_free(&g);
}

/* `scene torus` writes every test view's lines; eval scores against them. */
static void test_scene(const char *bin) {
    const char *dir = test_tmpdir("line_drawing");
    char out[4096], path[300];
    int rc = run_cmd(out, sizeof out, "%s scene torus --out %s/torus --views-train 24 --views-val 0 --views-test 2 "
                     "--size 96", bin, dir);
    CHECK(rc == 0 && strstr(out, "reference lines"), "scene torus: %d %s", rc, out);
    ws_status st;
    ws_status_clear(&st);
    static uint8_t part[96 * 96];
    snprintf(path, sizeof path, "%s/torus/lines/test", dir);
    for (int v = 0; v < 2; v++) {
        char name[16];
        snprintf(name, sizeof name, "r_%d", v);
        CHECK(ws_ref_lines_read(path, name, 96, 96, part, &st) == 0, "%s", st.msg);
        int sil = 0;
        for (int p = 0; p < 96 * 96; p++) sil += part[p] == WS_PART_SILHOUETTE;
        CHECK(sil > 40, "view %d: %d silhouette pixels", v, sil);
    }
    snprintf(path, sizeof path, "%s/torus/gt_curves.json", dir);
    CHECK(access(path, F_OK) != 0, "a smooth object has no ground-truth curves");
    /* a sketch: a ring about the torus's middle, eval scores it */
    snprintf(path, sizeof path, "%s/ring.json", dir);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL, "%s", path);
    if (f) {
        fprintf(f, "{\"thickness\": 0.01, \"overlap\": 0.6, \"curves\": [[[1.05, -0.2, 0.5], [1.05, 0.3, 0.5], "
                   "[0.8, 0.55, 0.5], [0.3, 0.55, 0.5]]]}\n");
        fclose(f);
    }
    rc = run_cmd(out, sizeof out, "%s eval %s/torus --curves %s --loss none --size 96", bin, dir, path);
    CHECK(rc == 0 && strstr(out, "\"drawing\": {\"views\": 2, \"overdraw\": ") && strstr(out, "\"precision_0.5\": "),
          "eval: %d %s", rc, out);
    /* the drawing draws the hull's outline beside the one curve, so it finds
     * far more of the reference lines than the curve alone */
    const char *d = strstr(out, "\"drawing\": {"), *c = strstr(out, "\"drawing_curves\": {");
    const char *rd = d ? strstr(d, "\"recall_1\": ") : NULL, *rcv = c ? strstr(c, "\"recall_1\": ") : NULL;
    double recall_drawing = rd ? atof(rd + 12) : -1, recall_curves = rcv ? atof(rcv + 12) : -1;
    CHECK(recall_drawing > 0.6 && recall_curves >= 0 && recall_curves < 0.5, "recall: drawing %g, curves alone %g",
          recall_drawing, recall_curves);
}

int main(void) {
    test_rules();
    test_scene(program_path());
    return check_summary();
}
