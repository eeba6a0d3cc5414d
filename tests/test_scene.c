/* test_scene.c: PNG input (every colour type and depth, alpha compositing,
 * resampling), scene loading (both layouts, missing splits, the committed
 * fixture scene; with a scenes folder as argument, the shared rose and
 * duck), every malformed input with its exact message, and the scene centre. Temporary scenes live in a mkdtemp directory. */
#include <math.h>
#include <png.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include "check.h"
#include "test_util.h"
#include "io/image.h"
#include "io/scene.h"

static const char *tmp;

static void path_in(char *out, const char *a, const char *b) { snprintf(out, 1024, "%s/%s", a, b); }

static void write_text(const char *path, const char *text) {
    FILE *fp = fopen(path, "wb");
    if (!fp) {
        perror(path);
        exit(1);
    }
    fputs(text, fp);
    fclose(fp);
}

/* Writes a PNG with libpng directly: `samples` holds the values of every
 * channel of the colour type (palette: indices), interleaved, one uint16
 * each; interlace: PNG_INTERLACE_NONE or PNG_INTERLACE_ADAM7. */
static void write_png(const char *path, int w, int h, int color_type, int depth, int interlace,
                      const uint16_t *samples, const png_color *palette, int npalette,
                      const png_byte *trns, int ntrns, const png_color_16 *trns_gray) {
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!fp || !info || setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "%s: cannot write test PNG\n", path);
        exit(1);
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, w, h, depth, color_type, interlace,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (palette) png_set_PLTE(png, info, palette, npalette);
    if (trns || trns_gray) png_set_tRNS(png, info, trns, ntrns, trns_gray);
    png_write_info(png, info);
    int nc = color_type == PNG_COLOR_TYPE_GRAY         ? 1
             : color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
             : color_type == PNG_COLOR_TYPE_RGB        ? 3
             : color_type == PNG_COLOR_TYPE_RGBA       ? 4
                                                       : 1;
    png_byte row[4096];
    const int passes = png_set_interlace_handling(png); /* each pass takes every row */
    for (int pass = 0; pass < passes; pass++) {
        for (int i = 0; i < h; i++) {
            memset(row, 0, sizeof row);
            for (int k = 0; k < w * nc; k++) {
                uint16_t v = samples[(size_t)i * w * nc + k];
                if (depth == 16) {
                    row[2 * k] = v >> 8;
                    row[2 * k + 1] = v & 255;
                } else if (depth == 8) {
                    row[k] = (png_byte)v;
                } else { /* packed, most significant bits first */
                    int bit = k * depth;
                    row[bit / 8] |= (png_byte)(v << (8 - depth - bit % 8));
                }
            }
            png_write_row(png, row);
        }
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

/* A small 8-bit RGB PNG, the image of a generated scene frame. */
static void write_rgb_png(const char *path, int w, int h, int seed) {
    uint16_t *s = malloc(sizeof *s * w * h * 3);
    for (int k = 0; k < w * h * 3; k++) s[k] = (uint16_t)((k * 7 + seed * 31) % 256);
    write_png(path, w, h, PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, s, NULL, 0, NULL, 0, NULL);
    free(s);
}

/* A camera at `pos` looking at `target`, z up (Blender): columns x, y, z of
 * the camera in world space, the camera looking down its -z. */
static void look_at(const double pos[3], const double target[3], double c2w[4][4]) {
    double z[3], x[3], y[3], up[3] = {0, 0, 1}, n = 0;
    for (int i = 0; i < 3; i++) z[i] = pos[i] - target[i];
    for (int i = 0; i < 3; i++) n += z[i] * z[i];
    for (int i = 0; i < 3; i++) z[i] /= sqrt(n);
    x[0] = up[1] * z[2] - up[2] * z[1];
    x[1] = up[2] * z[0] - up[0] * z[2];
    x[2] = up[0] * z[1] - up[1] * z[0];
    n = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int i = 0; i < 3; i++) x[i] /= n;
    y[0] = z[1] * x[2] - z[2] * x[1];
    y[1] = z[2] * x[0] - z[0] * x[2];
    y[2] = z[0] * x[1] - z[1] * x[0];
    for (int i = 0; i < 3; i++) {
        c2w[i][0] = x[i];
        c2w[i][1] = y[i];
        c2w[i][2] = z[i];
        c2w[i][3] = pos[i];
        c2w[3][i] = 0;
    }
    c2w[3][3] = 1;
}

/* transforms_SPLIT.json with n frames named `paths` and matrices c2w. */
static void write_transforms(const char *dir, const char *split, double angle, int n,
                             const char *const *paths, double (*c2w)[4][4]) {
    char path[1024], *text = malloc(1 << 20);
    int len = sprintf(text, "{\n  \"camera_angle_x\": %.17g,\n  \"frames\": [", angle);
    for (int k = 0; k < n; k++) {
        len += sprintf(text + len, "%s\n    {\"file_path\": \"%s\", \"transform_matrix\": [",
                       k ? "," : "", paths[k]);
        for (int i = 0; i < 4; i++)
            len += sprintf(text + len, "%s[%.17g, %.17g, %.17g, %.17g]", i ? ", " : "",
                           c2w[k][i][0], c2w[k][i][1], c2w[k][i][2], c2w[k][i][3]);
        len += sprintf(text + len, "]}");
    }
    sprintf(text + len, "\n  ]\n}\n");
    snprintf(path, sizeof path, "%s/transforms_%s.json", dir, split);
    write_text(path, text);
    free(text);
}

/* A fresh scene directory under tmp with `n` train frames train/r_K looking
 * at the origin from a ring; images (8 x 6 RGB) under SCENE/IMGROOT/train/
 * unless imgroot is NULL. */
static void make_scene(char *dir, const char *name, const char *imgroot, int n) {
    char sub[1024], path[1100];
    path_in(dir, tmp, name);
    mkdir(dir, 0777);
    const char *paths[16];
    char names[16][32];
    double c2w[16][4][4], target[3] = {0, 0, 0};
    for (int k = 0; k < n; k++) {
        double pos[3] = {4 * cos(2 * M_PI * k / n), 4 * sin(2 * M_PI * k / n), 1.5};
        look_at(pos, target, c2w[k]);
        snprintf(names[k], sizeof names[k], "train/r_%d", k);
        paths[k] = names[k];
    }
    write_transforms(dir, "train", 0.69, n, paths, c2w);
    if (!imgroot) return;
    snprintf(sub, sizeof sub, "%s/%s", dir, imgroot);
    mkdir(sub, 0777);
    strcat(sub, "/train");
    mkdir(sub, 0777);
    for (int k = 0; k < n; k++) {
        snprintf(path, sizeof path, "%s/r_%d.png", sub, k);
        write_rgb_png(path, 8, 6, k);
    }
}

static float px(const ws_image *im, int c, int i, int j) {
    return im->data[((size_t)c * im->height + i) * im->width + j];
}

/* Rewrites SCENE/transforms_train.json with `mask` (a JSON value) as the
 * mask_path of frame 0. */
static void set_mask_path(const char *dir, const char *mask) {
    char path[1100], text[1 << 14], out[1 << 14];
    snprintf(path, sizeof path, "%s/transforms_train.json", dir);
    FILE *fp = fopen(path, "rb");
    size_t n = fp ? fread(text, 1, sizeof text - 1, fp) : 0;
    if (fp) fclose(fp);
    text[n] = '\0';
    char *first = strstr(text, "{\"file_path\"");
    if (!first) return;
    snprintf(out, sizeof out, "%.*s{\"mask_path\": %s, %s", (int)(first - text), text, mask,
             first + 1);
    write_text(path, out);
}

/* A frame's mask_path: a gray PNG (left half white) becomes view 0's mask;
 * view 1 (no mask_path, RGB) has none; a missing or non-string mask_path
 * is an error naming the frame. */
static void test_mask_path(void) {
    char dir[1024], path[1100];
    make_scene(dir, "masked", "rgb", 2);
    uint16_t g[8 * 6];
    for (int k = 0; k < 8 * 6; k++) g[k] = k % 8 < 4 ? 255 : 0;
    snprintf(path, sizeof path, "%s/m0.png", dir);
    write_png(path, 8, 6, PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, g, NULL, 0, NULL, 0, NULL);
    set_mask_path(dir, "\"m0.png\"");
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = 8;
    opt.height = 6;
    ws_scene sc;
    ws_status st;
    int rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_OK, "mask_path scene: %s", st.msg);
    if (rc) return;
    const ws_image *m = &sc.split[WS_TRAIN].views[0].mask;
    int same = m->data && m->width == 8 && m->height == 6 && m->channels == 1;
    for (int k = 0; same && k < 8 * 6; k++) same &= m->data[k] == (k % 8 < 4);
    CHECK(same, "the mask is the mask_path image");
    CHECK(sc.split[WS_TRAIN].views[1].mask.data == NULL, "frame without mask_path: no mask");
    ws_scene_free(&sc);
    opt.load_images = 0;
    CHECK(ws_scene_load(&sc, dir, &opt, &st) == WS_OK && sc.split[WS_TRAIN].views[0].mask.data == NULL,
          "cameras only: no mask");
    ws_scene_free(&sc);
    opt.load_images = 1;
    char want[4096];
    make_scene(dir, "masked", "rgb", 2);
    set_mask_path(dir, "\"none\"");
    snprintf(want, sizeof want,
             "%s/transforms_train.json: frame 0: mask_path: image not found (tried %s/none.png, "
             "%s/rgb/none.png)",
             dir, dir, dir);
    rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "missing mask: %s", st.msg);
    make_scene(dir, "masked", "rgb", 2);
    set_mask_path(dir, "3");
    snprintf(want, sizeof want, "%s/transforms_train.json: frame 0: mask_path is not a string", dir);
    rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "mask_path 3: %s", st.msg);
    make_scene(dir, "masked", "rgb", 2);
    set_mask_path(dir, "\"../masked/m0.png\"");
    snprintf(want, sizeof want,
             "%s/transforms_train.json: frame 0: mask_path '../masked/m0.png' leaves the scene "
             "directory ('..')",
             dir);
    rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "mask_path out of the scene: %s", st.msg);
}

/* Views per split, the train split's angle, the focal length it gives at
 * the working width, and the centre, as known independently. */
static void check_scene_facts(const ws_scene *sc, const char *label, const int views[3], double angle,
                              const double center[3]) {
    CHECK(sc->split[WS_TRAIN].n == views[0] && sc->split[WS_VAL].n == views[1] &&
              sc->split[WS_TEST].n == views[2],
          "%s views %d %d %d", label, sc->split[0].n, sc->split[1].n, sc->split[2].n);
    CHECK(fabs(sc->camera_angle_x - angle) < 1e-15, "%s angle %.17g", label, sc->camera_angle_x);
    CHECK(fabs(sc->split[WS_TRAIN].views[0].cam.focal - 0.5 * sc->width / tan(0.5 * angle)) < 1e-9,
          "%s focal", label);
    for (int i = 0; i < 3; i++)
        CHECK(fabs(sc->center[i] - center[i]) < 1e-9, "%s centre[%d] %.17g vs %.17g", label, i,
              sc->center[i], center[i]);
}

/* The committed fixture (tools/make_scene_fixture.py): counts, angle,
 * centre and pixels, the values from that script's own decoder (zlib and
 * PNG unfiltering in Python, not libpng). Its val/r_1.png is 16-bit RGBA
 * with alpha 0 on the background. */
#define FIXTURE "tests/fixtures/scene_small"
static void test_fixture_scene(void) {
    ws_status st;
    ws_scene_options opt;
    ws_scene sc;
    ws_scene_options_default(&opt);
    CHECK(opt.width == 224 && opt.height == 224 && opt.load_images == 1 && opt.background[0] == 0,
          "defaults");
    opt.width = opt.height = 64; /* the files' size: no resampling */
    int rc = ws_scene_load(&sc, FIXTURE, &opt, &st);
    CHECK(rc == WS_OK, "fixture: %s", st.msg);
    if (rc) return;
    /* the script's solve; the object's centre */
    check_scene_facts(&sc, "fixture", (const int[3]){8, 2, 4}, 0.6911111611634243,
                      (const double[3]){0.3, -0.2, 0.5});
    const ws_view *v = &sc.split[WS_TRAIN].views[0], *v1 = &sc.split[WS_VAL].views[1];
    CHECK(!strcmp(v->image_path, FIXTURE "/rgb/train/r_0.png") && !strcmp(v1->name, "r_1"),
          "fixture paths %s %s", v->image_path, v1->name);
    const int spots[3][2] = {{47, 21}, {44, 26}, {0, 0}};
    const int rgb0[3][3] = {{236, 137, 50}, {0, 0, 0}, {0, 0, 0}};      /* 8-bit RGB */
    const int rgb1[3][3] = {{0, 0, 0}, {60909, 35209, 12850}, {0, 0, 0}}; /* 16-bit RGBA */
    for (int s = 0; s < 3; s++)
        for (int c = 0; c < 3; c++) {
            CHECK(px(&v->photo, c, spots[s][0], spots[s][1]) == (float)(rgb0[s][c] / 255.0),
                  "train r_0 (%d,%d) channel %d", spots[s][0], spots[s][1], c);
            CHECK(fabs(px(&v1->photo, c, spots[s][0], spots[s][1]) - rgb1[s][c] / 65535.0) < 1e-6,
                  "val r_1 16-bit (%d,%d) channel %d", spots[s][0], spots[s][1], c);
        }
    /* the 16-bit RGBA view's mask is its alpha; the RGB views have none */
    int ones = 0, agree = 1;
    if (v1->mask.data)
        for (int p = 0; p < 64 * 64; p++) {
            ones += v1->mask.data[p] == 1;
            agree &= v1->mask.data[p] == 0 || v1->mask.data[p] == 1;
        }
    CHECK(v1->mask.width == 64 && v1->mask.height == 64 && v1->mask.channels == 1 && agree &&
              ones == 376,
          "val r_1 mask: %d of 4096 pixels are object (the script counts 376)", ones);
    CHECK(v1->mask.data && v1->mask.data[44 * 64 + 26] == 1 && v1->mask.data[47 * 64 + 21] == 0,
          "val r_1 mask at the spots");
    CHECK(v->mask.data == NULL && sc.split[WS_VAL].views[0].mask.data == NULL,
          "no alpha, no mask");
    ws_scene_free(&sc);
    CHECK(sc.split[WS_TRAIN].n == 0 && sc.split[WS_TRAIN].views == NULL, "free empties");

    /* alpha 0 shows the background; the 8-bit files have no alpha */
    opt.background[0] = 0.25f;
    opt.background[1] = 0.5f;
    opt.background[2] = 1.0f;
    rc = ws_scene_load(&sc, FIXTURE, &opt, &st);
    CHECK(rc == WS_OK, "fixture on a background: %s", st.msg);
    if (rc) return;
    for (int c = 0; c < 3; c++) {
        CHECK(px(&sc.split[WS_VAL].views[1].photo, c, 0, 0) == opt.background[c],
              "transparent pixel shows the background, channel %d", c);
        CHECK(px(&sc.split[WS_TRAIN].views[0].photo, c, 0, 0) == 0, "opaque black stays black");
    }
    ws_scene_free(&sc);
}

/* The shared scenes (`make test-scenes SCENES=DIR`): rose and duck. */
static void test_shared_scenes(const char *scenes) {
    ws_status st;
    ws_scene_options opt;
    ws_scene sc;
    char rose[1024], duck[1024], path[1100];
    snprintf(rose, sizeof rose, "%s/rose", scenes);
    snprintf(duck, sizeof duck, "%s/duck", scenes);
    ws_scene_options_default(&opt);
    opt.load_images = 0;
    int rc = ws_scene_load(&sc, rose, &opt, &st);
    CHECK(rc == WS_OK, "rose cameras: %s", st.msg);
    if (rc) return;
    /* numpy's solve of the same normal equations over all 161 cameras */
    check_scene_facts(&sc, "rose", (const int[3]){96, 32, 33}, 0.6911112070083618,
                      (const double[3]){12.772500028617703, 13.175648676841869, 5.653980713535756});
    CHECK(!strcmp(sc.split[WS_TRAIN].views[0].name, "r_0"), "rose name %s",
          sc.split[0].views[0].name);
    CHECK(sc.split[WS_TRAIN].views[0].photo.data == NULL, "cameras only: no pixels");
    ws_scene_free(&sc);

    opt.load_images = 1;
    rc = ws_scene_load(&sc, rose, &opt, &st);
    CHECK(rc == WS_OK, "rose: %s", st.msg);
    if (rc) return;
    const ws_view *v = &sc.split[WS_TRAIN].views[0];
    snprintf(path, sizeof path, "%s/rgb/train/r_0.png", rose);
    CHECK(!strcmp(v->image_path, path), "rose path %s", v->image_path);
    CHECK(v->photo.width == 224 && v->photo.height == 224 && v->photo.channels == 3,
          "rose photo size");
    /* values from an independent decode (Python: zlib + numpy unfiltering,
     * agreeing with PIL) of rgb/train/r_0.png and rgb/val/r_5.png */
    const int spots[3][2] = {{100, 100}, {112, 112}, {0, 0}};
    const int rgb0[3][3] = {{207, 26, 33}, {202, 27, 28}, {1, 1, 1}};
    const int rgb5[3][3] = {{1, 1, 1}, {96, 104, 37}, {1, 1, 1}};
    const ws_view *v5 = &sc.split[WS_VAL].views[5];
    CHECK(!strcmp(v5->name, "r_5"), "val 5 is %s", v5->name);
    for (int s = 0; s < 3; s++)
        for (int c = 0; c < 3; c++) {
            CHECK(fabs(px(&v->photo, c, spots[s][0], spots[s][1]) - rgb0[s][c] / 255.0) < 1e-6,
                  "rose r_0 (%d,%d) channel %d", spots[s][0], spots[s][1], c);
            CHECK(fabs(px(&v5->photo, c, spots[s][0], spots[s][1]) - rgb5[s][c] / 255.0) < 1e-6,
                  "rose val r_5 (%d,%d) channel %d", spots[s][0], spots[s][1], c);
        }
    ws_scene_free(&sc);

    rc = ws_scene_load(&sc, duck, &opt, &st);
    CHECK(rc == WS_OK, "duck: %s", st.msg);
    if (rc) return;
    CHECK(sc.split[WS_TRAIN].n == 96 && sc.split[WS_VAL].n == 31 && sc.split[WS_TEST].n == 31,
          "duck views %d %d %d", sc.split[0].n, sc.split[1].n, sc.split[2].n);
    const int duck_px[2][3] = {{10536, 11386, 11905},
                               {26544, 21111, 20947}}; /* 16-bit, independent decode */
    for (int s = 0; s < 2; s++)
        for (int c = 0; c < 3; c++)
            CHECK(fabs(px(&sc.split[WS_TRAIN].views[0].photo, c, spots[s][0], spots[s][1]) -
                       duck_px[s][c] / 65535.0) < 1e-6,
                  "duck r_0 16-bit (%d,%d) channel %d", spots[s][0], spots[s][1], c);
    ws_scene_free(&sc);
}

/* Every colour type and depth there is but the palette (samples per pixel nc). */
static const struct {
    int type, depth, nc;
} kinds[] = {{PNG_COLOR_TYPE_GRAY, 8, 1},        {PNG_COLOR_TYPE_GRAY, 16, 1},
             {PNG_COLOR_TYPE_GRAY, 4, 1},        {PNG_COLOR_TYPE_GRAY_ALPHA, 8, 2},
             {PNG_COLOR_TYPE_GRAY_ALPHA, 16, 2}, {PNG_COLOR_TYPE_RGB, 8, 3},
             {PNG_COLOR_TYPE_RGB, 16, 3},        {PNG_COLOR_TYPE_RGBA, 8, 4},
             {PNG_COLOR_TYPE_RGBA, 16, 4}};

/* Every colour type and depth, composited on black and on another colour. */
static void test_png_formats(void) {
    char path[1024];
    ws_status st;
    ws_image im;
    const float black[3] = {0, 0, 0}, bg[3] = {0.2f, 0.4f, 0.6f};
    const float *bgs[2] = {black, bg};
    path_in(path, tmp, "fmt.png");
    const int w = 3, h = 2;
    for (size_t t = 0; t < sizeof kinds / sizeof kinds[0]; t++) {
        int nc = kinds[t].nc, depth = kinds[t].depth, maxv = (1 << depth) - 1;
        uint16_t s[3 * 2 * 4];
        for (int k = 0; k < w * h * nc; k++) s[k] = (uint16_t)((k * 40503u + 7 * t) % (maxv + 1));
        if (nc == 2 || nc == 4) { /* include fully transparent and opaque pixels */
            s[nc - 1] = 0;
            s[2 * nc - 1] = (uint16_t)maxv;
        }
        write_png(path, w, h, kinds[t].type, depth, PNG_INTERLACE_NONE, s, NULL, 0, NULL, 0, NULL);
        for (int b = 0; b < 2; b++) {
            int rc = ws_image_read(path, 0, 0, bgs[b], &im, &st);
            CHECK(rc == WS_OK, "type %d depth %d: %s", kinds[t].type, depth, st.msg);
            if (rc) continue;
            CHECK(im.width == w && im.height == h && im.channels == 3, "size");
            double err = 0;
            for (int i = 0; i < h; i++)
                for (int j = 0; j < w; j++) {
                    const uint16_t *p = s + (i * w + j) * nc;
                    double a = (nc == 2 || nc == 4) ? (double)p[nc - 1] / maxv : 1.0;
                    for (int c = 0; c < 3; c++) {
                        double value = (double)p[nc >= 3 ? c : 0] / maxv;
                        double want = a * value + (1 - a) * bgs[b][c];
                        err = fmax(err, fabs(px(&im, c, i, j) - want));
                    }
                }
            CHECK(err < 1e-6, "type %d depth %d background %d: error %g", kinds[t].type, depth, b,
                  err);
            ws_image_free(&im);
        }
    }

    /* palette with tRNS: entry 0 transparent, 1 half, 2 opaque (3 has no
     * tRNS entry: opaque) */
    const png_color pal[4] = {{255, 0, 0}, {0, 255, 0}, {10, 20, 30}, {200, 100, 50}};
    const png_byte trns[3] = {0, 128, 255};
    const uint16_t idx[6] = {0, 1, 2, 3, 2, 1};
    write_png(path, 3, 2, PNG_COLOR_TYPE_PALETTE, 8, PNG_INTERLACE_NONE, idx, pal, 4, trns, 3, NULL);
    int rc = ws_image_read(path, 0, 0, bg, &im, &st);
    CHECK(rc == WS_OK, "palette: %s", st.msg);
    if (!rc) {
        double err = 0;
        for (int k = 0; k < 6; k++) {
            const png_color *e = &pal[idx[k]];
            double a = idx[k] < 3 ? trns[idx[k]] / 255.0 : 1.0;
            double want[3] = {e->red / 255.0, e->green / 255.0, e->blue / 255.0};
            for (int c = 0; c < 3; c++)
                err = fmax(err, fabs(px(&im, c, k / 3, k % 3) - (a * want[c] + (1 - a) * bg[c])));
        }
        CHECK(err < 1e-6, "palette+tRNS error %g", err);
        ws_image_free(&im);
    }

    /* 16-bit gray with a tRNS colour key: that gray value becomes transparent */
    const uint16_t gray[6] = {1000, 5000, 1000, 65535, 0, 1000};
    png_color_16 key = {0};
    key.gray = 1000;
    write_png(path, 3, 2, PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_NONE, gray, NULL, 0, NULL, 0, &key);
    rc = ws_image_read(path, 0, 0, bg, &im, &st);
    CHECK(rc == WS_OK, "gray tRNS: %s", st.msg);
    if (!rc) {
        double err = 0;
        for (int k = 0; k < 6; k++)
            for (int c = 0; c < 3; c++)
                err = fmax(err, fabs(px(&im, c, k / 3, k % 3) -
                                     (gray[k] == 1000 ? bg[c] : gray[k] / 65535.0)));
        CHECK(err < 1e-6, "gray tRNS error %g", err);
        ws_image_free(&im);
    }

    /* write then read back: 8-bit rounding of clamped values */
    ws_image out;
    ws_image_alloc(&out, 4, 3, 3, &st);
    for (int k = 0; k < 36; k++) out.data[k] = (float)(k / 35.0 * 1.4 - 0.2);
    out.data[5] = NAN;
    rc = ws_png_write(path, &out, &st);
    CHECK(rc == WS_OK, "png write: %s", st.msg);
    rc = ws_image_read(path, 0, 0, black, &im, &st);
    CHECK(rc == WS_OK, "png read back: %s", st.msg);
    if (!rc) {
        int bad = 0;
        for (int k = 0; k < 36; k++) {
            float v = k == 5 ? 0 : fminf(fmaxf(out.data[k], 0), 1);
            bad += fabs(im.data[k] - round(255 * v) / 255.0) > 1e-6;
        }
        CHECK(bad == 0, "write/read round trip: %d values differ", bad);
        ws_image_free(&im);
    }
    ws_image_free(&out);
    char dir[1100];
    snprintf(dir, sizeof dir, "%.*s", (int)(strrchr(path, '/') - path), path);
    CHECK(temporaries_in(dir, strrchr(path, '/') + 1) == 0, "no temporary file left");
    ws_image gray1;
    ws_image_alloc(&gray1, 2, 2, 1, &st);
    for (int k = 0; k < 4; k++) gray1.data[k] = k / 3.0f;
    rc = ws_png_write(path, &gray1, &st);
    CHECK(rc == WS_OK, "gray write: %s", st.msg);
    if (!rc && !ws_image_read(path, 0, 0, black, &im, &st)) {
        CHECK(fabs(px(&im, 2, 1, 1) - 1.0f) < 1e-6 && fabs(px(&im, 0, 0, 1) - 85 / 255.0) < 1e-6,
              "gray written as gray");
        ws_image_free(&im);
    }
    ws_image_free(&gray1);
}

/* A photo in another format is named by its first bytes (a phone's HEIC,
 * a raw camera's TIFF, ...), with what to do; anything else is "not a PNG
 * or JPEG file". */
static void test_other_formats(void) {
    static const struct {
        const char *bytes;
        size_t len;
        const char *name;
    } files[] = {{"GIF89a\1\0\1\0", 10, "a GIF"},
                 {"\0\0\0\x18" "ftypheic\0\0\0\0", 16, "a HEIC"},
                 {"\0\0\0\x1c" "ftypmif1\0\0\0\0", 16, "a HEIF"},
                 {"\0\0\0\x1c" "ftypavif\0\0\0\0", 16, "an AVIF"},
                 {"RIFF\x24\0\0\0" "WEBPVP8 ", 16, "a WebP"},
                 {"II*\0\x08\0\0\0", 8, "a TIFF"},
                 {"MM\0*\0\0\0\x08", 8, "a TIFF"},
                 {"BM", 2, "a BMP"},
                 {"\x76\x2f\x31\x01\x02\0\0\0", 8, "an OpenEXR"},
                 {"\0\0\0\x0cjP  \r\n\x87\n", 12, "a JPEG 2000"},
                 {"RIFF\x24\0\0\0" "WAVEfmt ", 16, NULL},
                 {"hello, world", 12, NULL},
                 {"", 0, NULL}};
    char path[1024], want[1200];
    path_in(path, tmp, "other.png");
    const float black[3] = {0, 0, 0};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        FILE *fp = fopen(path, "wb");
        if (!fp) return;
        fwrite(files[k].bytes, 1, files[k].len, fp);
        fclose(fp);
        if (files[k].name)
            snprintf(want, sizeof want, "%s: %s image, not PNG or JPEG (convert it to JPEG or PNG)", path,
                     files[k].name);
        else
            snprintf(want, sizeof want, "%s: not a PNG or JPEG file", path);
        ws_image im;
        ws_status st;
        CHECK(ws_image_read(path, 0, 0, black, &im, &st) == WS_EINPUT && !strcmp(st.msg, want), "file %zu: %s",
              k, st.msg);
    }
}

/* A PNG decoded smaller (image.h ws_image_read_reduced) at 1, 2, 4 and 8:
 * each pixel the mean of its block of reduce x reduce composited colours
 * and its alpha the block's mean alpha, the last column and row of blocks
 * holding fewer pixels (11 x 7: no factor divides either side), computed
 * here from the samples written; for every colour type and depth, from a
 * file read a row at a time and from an interlaced one, read whole. */
static void test_png_reduced(void) {
    enum { w = 11, h = 7 };
    const float bg[3] = {0.2f, 0.4f, 0.6f};
    char path[1024];
    path_in(path, tmp, "reduced.png");
    for (size_t t = 0; t < sizeof kinds / sizeof kinds[0]; t++) {
        const int nc = kinds[t].nc, depth = kinds[t].depth, maxv = (1 << depth) - 1, has_alpha = nc == 2 || nc == 4;
        uint16_t s[w * h * 4];
        for (int k = 0; k < w * h * nc; k++) s[k] = (uint16_t)((k * 40503u + 11 * t) % (maxv + 1));
        for (int laced = 0; laced < 2; laced++) {
            write_png(path, w, h, kinds[t].type, depth, laced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, s, NULL, 0,
                      NULL, 0, NULL);
            for (int reduce = 1; reduce <= 8; reduce *= 2) {
                ws_image im, alpha;
                ws_status st;
                int reduced, file_size[2];
                int rc = ws_image_read_reduced(path, reduce, bg, &im, &alpha, &reduced, file_size, &st);
                const int ow = (w + reduce - 1) / reduce, oh = (h + reduce - 1) / reduce;
                CHECK(rc == WS_OK && reduced == reduce && im.width == ow && im.height == oh && file_size[0] == w &&
                          file_size[1] == h && !alpha.data == !has_alpha,
                      "type %d depth %d interlaced %d at 1/%d: rc %d, %d x %d, factor %d, file %d x %d: %s",
                      kinds[t].type, depth, laced, reduce, rc, im.width, im.height, reduced, file_size[0],
                      file_size[1], rc ? st.msg : "");
                if (rc || im.width != ow || im.height != oh || !alpha.data != !has_alpha) continue;
                double err = 0;
                for (int bi = 0; bi < oh; bi++)
                    for (int bj = 0; bj < ow; bj++) {
                        double want[4] = {0, 0, 0, 0};
                        int n = 0;
                        for (int i = bi * reduce; i < h && i < (bi + 1) * reduce; i++)
                            for (int j = bj * reduce; j < w && j < (bj + 1) * reduce; j++, n++) {
                                const uint16_t *p = s + (i * w + j) * nc;
                                const double a = has_alpha ? (double)p[nc - 1] / maxv : 1.0;
                                for (int c = 0; c < 3; c++)
                                    want[c] += a * p[nc >= 3 ? c : 0] / maxv + (1 - a) * bg[c];
                                want[3] += a;
                            }
                        for (int c = 0; c < 3; c++) err = fmax(err, fabs(px(&im, c, bi, bj) - want[c] / n));
                        if (has_alpha) err = fmax(err, fabs(px(&alpha, 0, bi, bj) - want[3] / n));
                    }
                CHECK(err < 1e-6, "type %d depth %d interlaced %d at 1/%d: error %g", kinds[t].type, depth, laced,
                      reduce, err);
                ws_image_free(&im);
                ws_image_free(&alpha);
            }
        }
    }
}
/* 448 -> 224 averages 2 x 2 blocks; 100 -> 224 is bilinear with pixel
 * centres aligned, so a linear ramp stays a linear ramp (clamped at the
 * borders), exactly. */
static void test_resample(void) {
    char path[1024];
    ws_status st;
    ws_image im;
    const float black[3] = {0, 0, 0};
    path_in(path, tmp, "big.png");
    uint16_t *s = malloc(sizeof *s * 448 * 448 * 3);
    for (int i = 0; i < 448; i++)
        for (int j = 0; j < 448; j++)
            for (int c = 0; c < 3; c++)
                s[(i * 448 + j) * 3 + c] = (uint16_t)((i * 7 + j * 13 + c * 50) % 256);
    write_png(path, 448, 448, PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, s, NULL, 0, NULL, 0, NULL);
    int rc = ws_image_read(path, 224, 224, black, &im, &st);
    CHECK(rc == WS_OK, "448: %s", st.msg);
    if (!rc) {
        double err = 0;
        for (int i = 0; i < 224; i++)
            for (int j = 0; j < 224; j++)
                for (int c = 0; c < 3; c++) {
                    double sum = 0;
                    for (int a = 0; a < 2; a++)
                        for (int b = 0; b < 2; b++)
                            sum += s[((2 * i + a) * 448 + 2 * j + b) * 3 + c];
                    err = fmax(err, fabs(px(&im, c, i, j) - sum / 4 / 255));
                }
        CHECK(im.width == 224 && im.height == 224 && err < 1e-5, "448 -> 224 block means: error %g",
              err);
        ws_image_free(&im);
    }
    free(s);

    path_in(path, tmp, "small.png");
    s = malloc(sizeof *s * 100 * 100);
    for (int i = 0; i < 100; i++)
        for (int j = 0; j < 100; j++) s[i * 100 + j] = (uint16_t)(i + 2 * j);
    write_png(path, 100, 100, PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_NONE, s, NULL, 0, NULL, 0, NULL);
    rc = ws_image_read(path, 224, 224, black, &im, &st);
    CHECK(rc == WS_OK, "100: %s", st.msg);
    if (!rc) {
        double err = 0;
        for (int i = 0; i < 224; i++)
            for (int j = 0; j < 224; j++) {
                double y = fmin(fmax((i + 0.5) * 100 / 224 - 0.5, 0), 99);
                double x = fmin(fmax((j + 0.5) * 100 / 224 - 0.5, 0), 99);
                err = fmax(err, fabs(px(&im, 1, i, j) - (y + 2 * x) / 65535));
            }
        CHECK(err < 1e-6, "100 -> 224 bilinear ramp: error %g", err);
        ws_image_free(&im);
    }
    free(s);

    /* non-integer shrink keeps the mean of a constant and of a ramp's total */
    ws_image a, b;
    ws_image_alloc(&a, 300, 7, 1, &st);
    for (int j = 0; j < 300; j++)
        for (int i = 0; i < 7; i++) a.data[i * 300 + j] = (float)j;
    rc = ws_image_resample(&a, 224, 5, &b, &st);
    CHECK(rc == WS_OK, "resample: %s", st.msg);
    if (!rc) {
        double sum = 0, err = 0;
        for (int j = 0; j < 224; j++) {
            sum += b.data[2 * 224 + j];
            /* output pixel j is the mean of input pixels k over [j s, (j + 1) s),
             * s = 300/224, each weighted by its overlap with that interval */
            double s300 = 300.0 / 224;
            double lo = j * s300, hi = (j + 1) * s300, integ = 0;
            for (int k = (int)floor(lo); k < hi && k < 300; k++)
                integ += k * (fmin(hi, k + 1) - fmax(lo, k));
            err = fmax(err, fabs(b.data[2 * 224 + j] - integ / s300));
        }
        CHECK(fabs(sum / 224 - 149.5) < 1e-3, "area mean preserved: %g", sum / 224);
        CHECK(err < 1e-3, "area weights: error %g", err);
        ws_image_free(&b);
    }
    ws_image_free(&a);
}

static void test_layouts(void) {
    char dir[1024], path[2048];
    ws_status st;
    ws_scene sc;
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = 16;
    opt.height = 12;

    make_scene(dir, "flat", ".", 3); /* SCENE/train/r_K.png */
    int rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_OK, "flat layout: %s", st.msg);
    if (!rc) {
        snprintf(path, sizeof path, "%s/train/r_2.png", dir);
        CHECK(sc.split[WS_TRAIN].n == 3 && !strcmp(sc.split[WS_TRAIN].views[2].image_path, path),
              "flat path %s", sc.split[WS_TRAIN].views[2].image_path);
        CHECK(sc.split[WS_VAL].n == 0 && sc.split[WS_TEST].n == 0, "missing val/test allowed");
        CHECK(sc.split[WS_TRAIN].views[1].photo.width == 16 &&
                  sc.split[WS_TRAIN].views[1].photo.height == 12,
              "resampled to the working size");
        CHECK(sc.split[WS_TRAIN].views[1].cam.width == 16, "camera at the working size");
        ws_scene_free(&sc);
    }

    make_scene(dir, "nested", "rgb", 3); /* SCENE/rgb/train/r_K.png */
    rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_OK, "rgb layout: %s", st.msg);
    if (!rc) {
        snprintf(path, sizeof path, "%s/rgb/train/r_0.png", dir);
        CHECK(!strcmp(sc.split[WS_TRAIN].views[0].image_path, path), "rgb path %s",
              sc.split[WS_TRAIN].views[0].image_path);
        ws_scene_free(&sc);
    }

    /* file_path with ".png" and with "./" is found too; a val split */
    double c2w[2][4][4], target[3] = {0, 0, 0}, p0[3] = {3, 0, 1}, p1[3] = {0, 3, 1};
    look_at(p0, target, c2w[0]);
    look_at(p1, target, c2w[1]);
    const char *paths[2] = {"train/r_0.png", "./train/r_1"};
    write_transforms(dir, "val", 0.5, 2, paths, c2w);
    rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_OK, "val with extensions: %s", st.msg);
    if (!rc) {
        snprintf(path, sizeof path, "%s/rgb/train/r_0.png", dir);
        CHECK(sc.split[WS_VAL].n == 2 && !strcmp(sc.split[WS_VAL].views[0].image_path, path) &&
                  !strcmp(sc.split[WS_VAL].views[0].name, "r_0") &&
                  !strcmp(sc.split[WS_VAL].views[1].name, "r_1"),
              "val views");
        CHECK(fabs(sc.split[WS_VAL].views[0].cam.focal - 8 / tan(0.25)) < 1e-12 &&
                  fabs(sc.camera_angle_x - 0.69) < 1e-15,
              "per-file camera_angle_x");
        ws_scene_free(&sc);
    }

    /* cameras only: no image is looked for */
    make_scene(dir, "noimages", NULL, 2);
    opt.load_images = 0;
    rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_OK && sc.split[WS_TRAIN].n == 2, "cameras only without images: %s", st.msg);
    if (!rc) ws_scene_free(&sc);
}

/* Loads a scene expecting failure with exactly `want`. */
static void expect_error(const char *dir, const char *want, int code) {
    ws_status st;
    ws_scene sc;
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    ws_status_clear(&st);
    int rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == code && st.code == code && !strcmp(st.msg, want),
          "expected \"%s\" (%d), got \"%s\" (%d)", want, code, st.msg, rc);
    CHECK(sc.split[WS_TRAIN].n == 0 && sc.split[WS_TRAIN].views == NULL,
          "failed load leaves nothing");
}

static void test_errors(void) {
    char dir[1024], path[2048], want[8192];

    make_scene(dir, "bad", "rgb", 4);
    snprintf(path, sizeof path, "%s/transforms_train.json", dir);
    char json[1024];

    write_text(path, "{\n  \"camera_angle_x\": 0.7,\n  \"frames\": [ ,\n  ]\n}\n");
    snprintf(want, sizeof want, "%s: JSON syntax error near line 3", path);
    expect_error(dir, want, WS_EINPUT);

    write_text(path, "{\"camera_angle_x\": 0.7,\n\"frames\": []}\n\n}\n");
    snprintf(want, sizeof want, "%s: JSON syntax error near line 4", path);
    expect_error(dir, want, WS_EINPUT);

    write_text(path, "{\"frames\": []}");
    snprintf(want, sizeof want, "%s: missing camera_angle_x", path);
    expect_error(dir, want, WS_EINPUT);

    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": []}");
    snprintf(want, sizeof want, "%s: no frames", path);
    expect_error(dir, want, WS_EINPUT);

    write_text(path, "[1, 2]");
    snprintf(want, sizeof want, "%s: not a JSON object", path);
    expect_error(dir, want, WS_EINPUT);

    const char *ok = "{\"file_path\": \"train/r_0\", \"transform_matrix\": "
                     "[[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]}";
    snprintf(json, sizeof json,
             "{\"camera_angle_x\": 0.7, \"frames\": [%s, {\"file_path\": \"train/r_1\", "
             "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,4]]}]}",
             ok);
    write_text(path, json);
    snprintf(want, sizeof want, "%s: frame 1: transform_matrix is not 4x4", path);
    expect_error(dir, want, WS_EINPUT);

    snprintf(json, sizeof json,
             "{\"camera_angle_x\": 0.7, \"frames\": [%s, %s, %s, {\"file_path\": \"train/r_3\", "
             "\"transform_matrix\": [[0,0,0,1],[0,0,0,2],[0,0,0,3],[0,0,0,1]]}]}",
             ok, ok, ok);
    write_text(path, json);
    snprintf(want, sizeof want, "%s: frame 3: transform_matrix is singular (det 0)", path);
    expect_error(dir, want, WS_EINPUT);

    snprintf(json, sizeof json,
             "{\"camera_angle_x\": 0.7, \"frames\": [%s, {\"file_path\": \"train/r_9\", "
             "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]}]}",
             ok);
    write_text(path, json);
    snprintf(want, sizeof want,
             "%s: frame 1: image not found (tried %s/train/r_9.png, %s/rgb/train/r_9.png)", path,
             dir, dir);
    expect_error(dir, want, WS_EINPUT);

    snprintf(json, sizeof json,
             "{\"camera_angle_x\": 0.7, \"frames\": [{\"transform_matrix\": 3}]}");
    write_text(path, json);
    snprintf(want, sizeof want, "%s: frame 0: missing file_path", path);
    expect_error(dir, want, WS_EINPUT);

    snprintf(json, sizeof json, "{\"camera_angle_x\": 4, \"frames\": [%s]}", ok);
    write_text(path, json);
    snprintf(want, sizeof want, "%s: camera_angle_x 4 is not in [0.001, pi - 0.001]", path);
    expect_error(dir, want, WS_EINPUT);

    /* an unreadable transforms file (a directory in its place) */
    remove(path);
    mkdir(path, 0777);
    snprintf(want, sizeof want, "%s: not a regular file", path);
    expect_error(dir, want, WS_EINPUT);
    rmdir(path);

    snprintf(want, sizeof want,
             "%s: missing (a scene needs a train split, a transforms.json or a COLMAP model in "
             "sparse/0, sparse or the folder)",
             path);
    expect_error(dir, want, WS_EINPUT);

    /* PNG errors name the PNG; the lowest bad frame wins whatever the schedule */
    make_scene(dir, "badpng", "rgb", 4);
    char png1[2048], png3[2048];
    snprintf(png1, sizeof png1, "%s/rgb/train/r_1.png", dir);
    snprintf(png3, sizeof png3, "%s/rgb/train/r_3.png", dir);
    write_text(png3, "GIF89a, not a PNG at all");
    snprintf(want, sizeof want, "%s: a GIF image, not PNG or JPEG (convert it to JPEG or PNG)", png3);
    expect_error(dir, want, WS_EINPUT);

    FILE *fp = fopen(png1, "rb");
    unsigned char bytes[4096];
    size_t n = fread(bytes, 1, sizeof bytes, fp);
    fclose(fp);
    fp = fopen(png1, "wb");
    fwrite(bytes, 1, n - 30, fp); /* cut inside the image data */
    fclose(fp);
    for (int rep = 0; rep < 5; rep++) {
        snprintf(want, sizeof want, "%s: truncated or corrupt PNG (unexpected end of file)", png1);
        expect_error(dir, want, WS_EINPUT);
    }

    fp = fopen(png1, "wb");
    bytes[45] ^= 0x55; /* inside the first IDAT's data: zlib or the CRC check objects */
    fwrite(bytes, 1, n, fp);
    fclose(fp);
    ws_status st;
    ws_scene sc;
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    snprintf(want, sizeof want, "%s: truncated or corrupt PNG (", png1);
    int rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_EINPUT && !strncmp(st.msg, want, strlen(want)), "corrupt IDAT: %s", st.msg);

    fp = fopen(png1, "wb");
    bytes[45] ^= 0x55;
    bytes[30] ^= 0x55; /* the IHDR's CRC */
    fwrite(bytes, 1, n, fp);
    fclose(fp);
    snprintf(want, sizeof want, "%s: truncated or corrupt PNG (IHDR: CRC error)", png1);
    expect_error(dir, want, WS_EINPUT);

    fp = fopen(png1, "wb");
    bytes[30] ^= 0x55;
    fwrite(bytes, 1, 12, fp); /* signature and a few bytes of IHDR */
    fclose(fp);
    snprintf(want, sizeof want, "%s: truncated or corrupt PNG (unexpected end of file)", png1);
    expect_error(dir, want, WS_EINPUT);

    remove(png1);
    mkdir(png1, 0777);
    snprintf(want, sizeof want, "%s: not a regular file", png1);
    expect_error(dir, want, WS_EINPUT);
    rmdir(png1);

    if (geteuid() != 0) { /* root reads anything */
        write_rgb_png(png1, 8, 6, 1);
        chmod(png1, 0);
        snprintf(want, sizeof want, "%s: cannot open: Permission denied", png1);
        expect_error(dir, want, WS_EINPUT);
        chmod(png1, 0644);
    }

    /* absurd dimensions are refused before anything is allocated */
    uint16_t one = 0;
    write_png(png1, 1, 1, PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, &one, NULL, 0, NULL, 0, NULL);
    fp = fopen(png1, "rb");
    n = fread(bytes, 1, sizeof bytes, fp);
    fclose(fp);
    /* width = height = 20000 (bytes 16..23 of the file), then the IHDR CRC */
    for (int k = 0; k < 2; k++) {
        bytes[16 + 4 * k + 2] = 20000 >> 8;
        bytes[16 + 4 * k + 3] = 20000 & 255;
    }
    uint32_t crc = (uint32_t)crc32(0, bytes + 12, 17);
    bytes[29] = crc >> 24;
    bytes[30] = crc >> 16;
    bytes[31] = crc >> 8;
    bytes[32] = crc;
    fp = fopen(png1, "wb");
    fwrite(bytes, 1, n, fp);
    fclose(fp);
    ws_image im;
    const float black[3] = {0, 0, 0};
    rc = ws_image_read(png1, 0, 0, black, &im, &st);
    snprintf(want, sizeof want, "%s: image too large (20000 x 20000 pixels)", png1);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "huge image: %s", st.msg);

    snprintf(path, sizeof path, "%s/missing.png", tmp);
    rc = ws_image_read(path, 0, 0, black, &im, &st);
    snprintf(want, sizeof want, "%s: cannot open: No such file or directory", path);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "missing PNG: %s", st.msg);

    snprintf(path, sizeof path, "%s/nonexistent", tmp);
    snprintf(want, sizeof want, "%s: cannot open scene directory: No such file or directory", path);
    expect_error(path, want, WS_EINPUT);
}

/* Cameras on a ring, looking at its centre: the centre to 1e-9. Cameras
 * with parallel axes: the fallback (the mean camera position). */
static void test_center(void) {
    char dir[1024];
    path_in(dir, tmp, "ring");
    mkdir(dir, 0777);
    double c2w[12][4][4], c[3] = {1.5, -2.0, 0.7};
    const char *paths[12] = {"a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l"};
    for (int k = 0; k < 12; k++) {
        double ang = 2 * M_PI * k / 12 + 0.3;
        double pos[3] = {c[0] + 4 * cos(ang), c[1] + 4 * sin(ang), c[2] + 1.0 + 0.5 * (k % 3)};
        look_at(pos, c, c2w[k]);
    }
    write_transforms(dir, "train", 0.69, 8, paths, c2w);
    write_transforms(dir, "test", 0.69, 4, paths + 8, c2w + 8);
    ws_status st;
    ws_scene sc;
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.load_images = 0;
    int rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_OK, "ring: %s", st.msg);
    if (!rc) {
        for (int i = 0; i < 3; i++)
            CHECK(fabs(sc.center[i] - c[i]) < 1e-9, "ring centre[%d] %.17g vs %g", i, sc.center[i],
                  c[i]);
        CHECK(sc.split[WS_TEST].n == 4 && sc.split[WS_VAL].n == 0, "ring splits");
        ws_scene_free(&sc);
    }

    double mean[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        double pos[3] = {k * 1.0, k * k * 0.5, 2.0 + k};
        /* looking straight down the world's -z */
        double m[4][4] = {{1, 0, 0, pos[0]}, {0, 1, 0, pos[1]}, {0, 0, 1, pos[2]}, {0, 0, 0, 1}};
        memcpy(c2w[k], m, sizeof m);
        for (int i = 0; i < 3; i++) mean[i] += pos[i] / 3;
    }
    write_transforms(dir, "train", 0.69, 3, paths, c2w);
    char testjson[1100];
    snprintf(testjson, sizeof testjson, "%s/transforms_test.json", dir);
    remove(testjson);
    rc = ws_scene_load(&sc, dir, &opt, &st);
    CHECK(rc == WS_OK, "parallel: %s", st.msg);
    if (!rc) {
        for (int i = 0; i < 3; i++)
            CHECK(isfinite(sc.center[i]) && fabs(sc.center[i] - mean[i]) < 1e-12,
                  "parallel axes centre[%d] %g vs %g", i, sc.center[i], mean[i]);
        ws_scene_free(&sc);
    }
}

/* With a scenes folder as argument (make test-scenes), only the shared
 * scenes are checked; without, everything else. */
int main(int argc, char **argv) {
    if (argc > 1) {
        test_shared_scenes(argv[1]);
        return check_summary();
    }
    tmp = test_tmpdir("scene");
    test_png_formats();
    test_png_reduced();
    test_other_formats();
    test_resample();
    test_layouts();
    test_errors();
    test_center();
    test_fixture_scene();
    test_mask_path();
    return check_summary();
}
