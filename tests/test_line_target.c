/* test_line_target.c: the line loss's target (objective/line_target.h): a
 * thin bar becomes one line on its axis while a wide square keeps the
 * outline the thin edges give it, whatever the contrast, on black or white,
 * with a mask or without; a photo without thin parts keeps its thin edges
 * as they are. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "geometry/silhouette.h"
#include "io/image.h"
#include "objective/line_target.h"
#include "render/thin_edges.h"

/* 224 px wide, the fits' size: thin parts are those up to about 10 px wide */
enum { W = 224, H = 64, SPLIT = 40 };
/* the bar: columns 20..24 (5 px wide, axis column 22), rows 8..55; the
 * square: columns 50..79, rows 17..46 (30 px); columns below SPLIT show
 * the bar, the others the square */
static int bar(int i, int j) { return j >= 20 && j <= 24 && i >= 8 && i <= 55; }
static int square(int i, int j) { return j >= 50 && j <= 79 && i >= 17 && i <= 46; }

static void draw(ws_image *photo, float back, float object, int with_bar) {
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++)
                photo->data[(c * H + i) * W + j] = (with_bar && bar(i, j)) || square(i, j) ? object : back;
}

/* ws_line_target of the photo and mask with their silhouette. */
static int target(const ws_image *photo, const ws_image *mask, float *e, ws_status *st) {
    ws_silhouette sil;
    if (ws_silhouette_make(photo, mask, &sil, st)) return st->code;
    int rc = ws_line_target(photo, mask, &sil, NULL, e, st);
    ws_silhouette_free(&sil);
    return rc;
}

/* The target of a photo of the bar and the square: the bar's axis, column
 * 22 from row 10 to row 53 and nothing else beside the bar; the square's
 * thin edges (and the mask's outline where there is a mask). */
static void check_target(const ws_image *photo, const ws_image *mask, const char *what) {
    ws_status st;
    float *e = malloc(W * H * sizeof *e), *thin = malloc(W * H * sizeof *thin);
    CHECK(target(photo, mask, e, &st) == WS_OK && ws_thin_edges(photo->data, W, H, thin, &st) == WS_OK,
          "%s: %s", what, st.msg);
    if (mask) ws_thin_edges_add_outline(mask->data, W, H, thin);
    int axis = 0, off_axis = 0, outline = 0, square_same = 1, square_edges = 0;
    for (int i = 0; i < H; i++) {
        outline += thin[i * W + 19] || thin[i * W + 20] || thin[i * W + 24] || thin[i * W + 25];
        for (int j = 0; j < W; j++) {
            float v = e[i * W + j];
            if (j >= SPLIT) {
                square_same &= v == thin[i * W + j];
                square_edges += v != 0;
            } else if (v != 0 && j == 22 && i >= 10 && i <= 53) {
                axis++;
            } else {
                off_axis += v != 0;
            }
        }
    }
    CHECK(outline > 40, "%s: the thin edges draw no outline of the bar (%d rows)", what, outline);
    CHECK(axis == 44 && off_axis == 0, "%s: bar: %d of 44 axis pixels, %d pixels off the axis", what, axis,
          off_axis);
    CHECK(square_same && square_edges >= 4 * 29, "%s: square: not its thin edges (%d edge pixels)", what,
          square_edges);
    free(e);
    free(thin);
}

/* With the hull's support (line_evidence.h): a texture edge inside the
 * square (a darker stripe, rows 30..46) is dropped where nothing supports
 * it and kept where something does; the outline stays either way. */
static void test_support(void) {
    ws_status st;
    ws_image photo;
    ws_silhouette sil;
    float *e = malloc(W * H * sizeof *e), *plain = malloc(W * H * sizeof *plain);
    uint8_t *support = calloc(W * H, 1);
    CHECK(ws_image_alloc(&photo, W, H, 3, &st) == 0, "%s", st.msg);
    draw(&photo, 0, 0.8f, 0);
    for (int c = 0; c < 3; c++)
        for (int i = 30; i <= 46; i++)
            for (int j = 50; j <= 79; j++) photo.data[(c * H + i) * W + j] = 0.4f;
    CHECK(ws_silhouette_make(&photo, NULL, &sil, &st) == 0, "%s", st.msg);
    CHECK(ws_line_target(&photo, NULL, &sil, NULL, plain, &st) == 0, "%s", st.msg);
    for (int j = 50; j < 65; j++) support[29 * W + j] = support[30 * W + j] = support[31 * W + j] = 1;
    CHECK(ws_line_target(&photo, NULL, &sil, support, e, &st) == 0, "%s", st.msg);
    int stripe = 0, kept = 0, outline_same = 1;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            int inner = i >= 19 && i <= 44 && j >= 52 && j <= 77; /* > 2.5 px inside */
            if (!inner) outline_same &= e[i * W + j] == plain[i * W + j];
            if (inner && plain[i * W + j] != 0) stripe++;
            if (inner && e[i * W + j] != 0) kept += support[i * W + j] ? 1 : 1000;
        }
    CHECK(stripe > 10, "the stripe's edge: %d pixels", stripe);
    CHECK(kept > 0 && kept < 1000, "inside: %d supported pixels kept, %d unsupported", kept % 1000, kept / 1000);
    CHECK(outline_same, "the outline band changes with the support");
    ws_silhouette_free(&sil);
    ws_image_free(&photo);
    free(e);
    free(plain);
    free(support);
}

int main(void) {
    test_support();
    ws_status st;
    ws_image photo, mask;
    if (ws_image_alloc(&photo, W, H, 3, &st) || ws_image_alloc(&mask, W, H, 1, &st)) return 1;
    draw(&photo, 0, 0.8f, 1);
    check_target(&photo, NULL, "bright on black");
    draw(&photo, 0, 0.08f, 1);
    check_target(&photo, NULL, "a tenth of the contrast");
    draw(&photo, 1, 0.2f, 1);
    check_target(&photo, NULL, "dark on white");
    draw(&photo, 0, 0.8f, 1);
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) mask.data[i * W + j] = bar(i, j) || square(i, j);
    check_target(&photo, &mask, "with a mask");
    /* no thin part: the thin edges as they are */
    float *e = malloc(W * H * sizeof *e), *thin = malloc(W * H * sizeof *thin);
    draw(&photo, 0, 0.8f, 0);
    CHECK(target(&photo, NULL, e, &st) == WS_OK && ws_thin_edges(photo.data, W, H, thin, &st) == WS_OK &&
              !memcmp(e, thin, W * H * sizeof *e),
          "a square alone: the target is not its thin edges");
    free(e);
    free(thin);
    ws_image_free(&photo);
    ws_image_free(&mask);
    return check_summary();
}
