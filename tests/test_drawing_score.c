/* test_drawing_score.c: the 2D drawing score (metrics/drawing_score.h) on a
 * hand-made reference whose values are counted by hand, Zhang-Suen thinning
 * (render/skeleton.h), and the reference line files (io/ref_lines.h): their
 * round trip and the exact messages for bad files. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "io/image.h"
#include "io/ref_lines.h"
#include "metrics/drawing_score.h"
#include "render/skeleton.h"

#define W 200
#define H 200

/* The reference: the outline of the square of rows and columns 50..149
 * (396 silhouette pixels) over its mask, an inner contour down column 100
 * (rows 60..139, 80 px) and a crease along row 80 (columns 110..139, 30 px). */
static void make_reference(uint8_t *part) {
    memset(part, WS_PART_BACKGROUND, W * H);
    for (int i = 50; i < 150; i++)
        for (int j = 50; j < 150; j++)
            part[i * W + j] = (i == 50 || i == 149 || j == 50 || j == 149) ? WS_PART_SILHOUETTE : WS_PART_MASK;
    for (int i = 60; i < 140; i++) part[i * W + 100] = WS_PART_CONTOUR;
    for (int j = 110; j < 140; j++) part[80 * W + j] = WS_PART_CREASE;
}

static void draw_row(unsigned char *gray, int i, int j0, int j1) {
    for (int j = j0; j <= j1; j++) gray[i * W + j] = 0;
}

static void test_hand_counted(void) {
    static uint8_t part[W * H];
    static unsigned char gray[W * H];
    make_reference(part);
    memset(gray, 255, sizeof gray);
    draw_row(gray, 50, 50, 149); /* on the top outline: 100 px */
    draw_row(gray, 120, 60, 89); /* inside, 11 px from any line: 30 px of scribble */
    draw_row(gray, 20, 60, 79);  /* outside the object, far: 20 px */
    for (int j = 0; j < W; j++) gray[190 * W + j] = 127 + (j % 2); /* 127: stroke, 128: none */
    ws_status st;
    ws_status_clear(&st);
    ws_drawing_score s;
    CHECK(ws_drawing_score_view(gray, part, W, H, &s, &st) == 0, "%s", st.msg);
    /* row 190: every other pixel, 100 isolated specks far from the object */
    const double ns = 250, nr = 506, nc = 476;
    CHECK(s.views == 1 && s.contour_views == 1, "views %d %d", s.views, s.contour_views);
    CHECK(check_close(s.overdraw, ns / nr, 1e-12, 1), "overdraw %g", s.overdraw);
    /* tau 2.83 px: the top row, and rows 51, 52 of the outline's two sides */
    CHECK(check_close(s.precision[0], 100 / ns, 1e-12, 1), "precision %g", s.precision[0]);
    CHECK(check_close(s.recall[0], 104 / nr, 1e-12, 1), "recall %g", s.recall[0]);
    CHECK(check_close(s.contour_recall[0], 104 / nc, 1e-12, 1), "contour recall %g", s.contour_recall[0]);
    CHECK(check_close(s.scribble[0], 30 / ns, 1e-12, 1), "scribble %g", s.scribble[0]);
    double P = 100 / ns, R = 104 / nr;
    CHECK(check_close(s.fscore[0], 2 * P * R / (P + R), 1e-12, 1), "F %g", s.fscore[0]);
    /* tau 1.41 px: row 51 only */
    CHECK(check_close(s.recall[1], 102 / nr, 1e-12, 1), "recall at 0.5%% %g", s.recall[1]);
    CHECK(check_close(s.contour_recall[1], 102 / nc, 1e-12, 1), "contour recall at 0.5%% %g", s.contour_recall[1]);

    /* nothing drawn: all 0; no reference line: the view is not scored */
    memset(gray, 255, sizeof gray);
    CHECK(ws_drawing_score_view(gray, part, W, H, &s, &st) == 0 && s.views == 1 && s.precision[0] == 0 &&
              s.recall[0] == 0 && s.fscore[0] == 0 && s.overdraw == 0 && s.scribble[0] == 0,
          "empty sketch: P %g R %g", s.precision[0], s.recall[0]);
    memset(part, WS_PART_MASK, sizeof part);
    draw_row(gray, 50, 50, 149);
    CHECK(ws_drawing_score_view(gray, part, W, H, &s, &st) == 0 && s.views == 0, "no lines: views %d", s.views);
}

/* A stroke 3 px wide on the top outline thins to one line on it. */
static void test_thick_stroke(void) {
    static uint8_t part[W * H], set[W * H];
    static unsigned char gray[W * H];
    make_reference(part);
    memset(gray, 255, sizeof gray);
    for (int i = 49; i <= 51; i++) draw_row(gray, i, 50, 149);
    ws_status st;
    ws_status_clear(&st);
    ws_drawing_score s;
    CHECK(ws_drawing_score_view(gray, part, W, H, &s, &st) == 0, "%s", st.msg);
    CHECK(s.precision[1] == 1, "thick stroke: precision %g", s.precision[1]);
    /* one pixel per column, but for the ends */
    CHECK(s.overdraw * 506 >= 96 && s.overdraw * 506 <= 100, "thick stroke: %g pixels", s.overdraw * 506);
    for (int p = 0; p < W * H; p++) set[p] = gray[p] < 128;
    CHECK(ws_skeleton_thin(set, W, H, &st) == 0, "%s", st.msg);
    int blocks = 0;
    for (int i = 0; i + 1 < H; i++)
        for (int j = 0; j + 1 < W; j++)
            blocks += set[i * W + j] && set[i * W + j + 1] && set[(i + 1) * W + j] && set[(i + 1) * W + j + 1];
    CHECK(blocks == 0, "thinned: %d 2 x 2 blocks", blocks);
}

static void test_files(void) {
    const char *dir = test_tmpdir("drawing");
    static uint8_t part[W * H], back[W * H];
    make_reference(part);
    ws_status st;
    ws_status_clear(&st);
    CHECK(ws_ref_lines_write(dir, "r_0", part, W, H, &st) == 0, "%s", st.msg);
    CHECK(ws_ref_lines_read(dir, "r_0", W, H, back, &st) == 0 && !memcmp(part, back, sizeof part), "round trip: %s",
          st.msg);
    char path[300], want[400];
    CHECK(ws_ref_lines_read(dir, "r_0", 100, 200, back, &st) != 0, "wrong size accepted");
    snprintf(want, sizeof want, "%s/r_0.png: 200 x 200 pixels, the view is 100 x 200", dir);
    CHECK(!strcmp(st.msg, want), "message: %s", st.msg);
    /* a line pixel of the parts file that the lines file lacks */
    ws_image img;
    CHECK(ws_image_alloc(&img, W, H, 1, &st) == 0, "%s", st.msg);
    for (int p = 0; p < W * H; p++) img.data[p] = ws_part_is_line(part[p]);
    img.data[50 * W + 60] = 0;
    snprintf(path, sizeof path, "%s/r_0.png", dir);
    CHECK(ws_png_write(path, &img, &st) == 0, "%s", st.msg);
    CHECK(ws_ref_lines_read(dir, "r_0", W, H, back, &st) != 0, "mismatch accepted");
    snprintf(want, sizeof want, "%s/r_0.png: pixel (row 50, column 60) is a line in r_0_parts.png but not here", dir);
    CHECK(!strcmp(st.msg, want), "message: %s", st.msg);
    ws_image_free(&img);
    /* a colour that is no part */
    part[3 * W + 5] = WS_PART_MASK;
    CHECK(ws_ref_lines_write(dir, "r_1", part, W, H, &st) == 0, "%s", st.msg);
    ws_image rgb;
    snprintf(path, sizeof path, "%s/r_1_parts.png", dir);
    const float black[3] = {0, 0, 0};
    CHECK(ws_image_read(path, 0, 0, black, &rgb, &st) == 0, "%s", st.msg);
    rgb.data[3 * W + 5] = 1 / 255.0f; /* red of (48,48,48) becomes 1 */
    CHECK(ws_png_write(path, &rgb, &st) == 0, "%s", st.msg);
    CHECK(ws_ref_lines_read(dir, "r_1", W, H, back, &st) != 0, "bad colour accepted");
    snprintf(want, sizeof want, "%s: pixel (row 3, column 5) is (1,48,48), not one of the five part colours", path);
    CHECK(!strcmp(st.msg, want), "message: %s", st.msg);
    ws_image_free(&rgb);
}

int main(void) {
    test_hand_counted();
    test_thick_stroke();
    test_files();
    return check_summary();
}
