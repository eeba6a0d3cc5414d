/* test_capture.c: captures as photogrammetry writes them (JPEG, COLMAP
 * models text and binary, lenses), made by `wiresketch scene`:
 * - the same scene through an OPENCV lens as nerfstudio, binary COLMAP
 *   and text COLMAP loads to the same photos (within a grey level) and
 *   cameras (within 1e-9), and to the same sparse points (COLMAP's
 *   points3D, nerfstudio's ply_file_path);
 * - JPEG images load within a few grey levels of the PNG ones, a
 *   progressive JPEG decodes as its baseline twin, and PNG's size limit
 *   holds; a large JPEG or PNG is decoded at the scale its working view
 *   needs, to the photos the PNG gives decoded whole, and its mask at the
 *   same scale, to the masks decoded whole;
 * - undistortion undoes the lens: the lens scene's photos match the
 *   pinhole scene's;
 * - each bad input against its exact one-line message: a truncated and a
 *   CMYK JPEG, an unknown camera model, an image id with no file, NaN in
 *   points3D, a truncated binary model, lens values that fold the image,
 *   a nerfstudio ply_file_path that is no file name, leaves the scene's
 *   folder, or holds NaN;
 * - a small object in a large frame (a wide lens): loaded as every command
 *   loads it (geometry/roi.h ws_roi_load_scene), each working view zooms
 *   onto the sparse points' box, shows the whole object larger than the
 *   largest crop does, and magnifies nothing; the COLMAP twin zooms the
 *   same way, and the crop line says so. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <jpeglib.h>
#include "check.h"
#include "test_util.h"
#include "geometry/roi.h"
#include "io/image.h"
#include "io/pointcloud.h"
#include "io/scene_crops.h"
#include "io/scene.h"
#include "io/undistort.h"
#include "scene_load.h"

static char bin[1024];
static const char *tmp;

#define SCENE_ARGS "--width 80 --height 60 --views-train 6 --views-val 1 --views-test 1"
#define LENS "--lens -0.25,0.06,0.002,-0.001"

static double max_diff(const ws_image *a, const ws_image *b, double *mean) {
    if (a->width != b->width || a->height != b->height || a->channels != b->channels) return INFINITY;
    double worst = 0, sum = 0;
    const size_t n = (size_t)a->width * a->height * a->channels;
    for (size_t k = 0; k < n; k++) {
        worst = fmax(worst, fabs(a->data[k] - b->data[k]));
        sum += fabs(a->data[k] - b->data[k]);
    }
    if (mean) *mean = sum / n;
    return worst;
}

static double camera_diff(const ws_camera *a, const ws_camera *b) {
    double worst = fmax(fabs(a->focal - b->focal), fmax(fabs(a->cx - b->cx), fabs(a->cy - b->cy)));
    for (int i = 0; i < 3; i++) {
        worst = fmax(worst, fabs(a->t[i] - b->t[i]));
        for (int j = 0; j < 3; j++) worst = fmax(worst, fabs(a->R[i][j] - b->R[i][j]));
    }
    return worst + abs(a->width - b->width) + abs(a->height - b->height);
}

/* The largest photo and camera differences of two scenes, view by view
 * (mean: the largest per-view mean photo difference); -1 when their
 * splits differ. */
static int compare(const ws_scene *a, const ws_scene *b, double *photos, double *mean,
                   double *cameras) {
    *photos = *mean = *cameras = 0;
    for (int s = 0; s < WS_NSPLITS; s++) {
        if (a->split[s].n != b->split[s].n) return -1;
        for (int k = 0; k < a->split[s].n; k++) {
            double m;
            *photos = fmax(*photos, max_diff(&a->split[s].views[k].photo, &b->split[s].views[k].photo, &m));
            *mean = fmax(*mean, m);
            *cameras = fmax(*cameras, camera_diff(&a->split[s].views[k].cam, &b->split[s].views[k].cam));
        }
    }
    return 0;
}

static int load(ws_scene *sc, const char *name, ws_status *st) {
    char dir[400];
    snprintf(dir, sizeof dir, "%s/%s", tmp, name);
    return load_scene_at(sc, dir, 48, st);
}

/* The message of loading scene `name`, with tmp's path replaced by "T". */
static const char *load_error(const char *name) {
    static char msg[1200];
    ws_scene sc;
    ws_status st;
    if (!load(&sc, name, &st)) {
        ws_scene_free(&sc);
        return "(loaded)";
    }
    size_t n = 0;
    for (const char *c = st.msg; *c && n + 1 < sizeof msg;) {
        if (!strncmp(c, tmp, strlen(tmp))) {
            msg[n++] = 'T';
            c += strlen(tmp);
        } else {
            msg[n++] = *c++;
        }
    }
    msg[n] = '\0';
    return msg;
}

static void test_formats(void) {
    char out[1 << 14];
    int rc = run_cmd(out, sizeof out,
                     "cd %s && %s scene cube " SCENE_ARGS " " LENS " --layout nerfstudio --out ns && "
                     "%s scene cube " SCENE_ARGS " " LENS " --layout colmap --out cb && "
                     "%s scene cube " SCENE_ARGS " " LENS " --layout colmap-text --out ct && "
                     "%s scene cube " SCENE_ARGS " " LENS " --layout colmap --jpeg --out cj && "
                     "%s scene cube " SCENE_ARGS " " LENS " --layout nerfstudio --jpeg --out nj && "
                     "%s scene cube " SCENE_ARGS " --layout nerfstudio --out pin",
                     tmp, bin, bin, bin, bin, bin, bin);
    CHECK(rc == 0, "scenes: %s", out);
    ws_scene ns, cb, ct, cj, nj, pin;
    ws_status st;
    if (load(&ns, "ns", &st) || load(&cb, "cb", &st) || load(&ct, "ct", &st) ||
        load(&cj, "cj", &st) || load(&nj, "nj", &st) || load(&pin, "pin", &st)) {
        CHECK(0, "loading: %s", st.msg);
        return;
    }
    CHECK(cb.layout == WS_LAYOUT_COLMAP && ct.layout == WS_LAYOUT_COLMAP && ns.layout == WS_LAYOUT_NERFSTUDIO,
          "layouts detected");
    CHECK(!ws_lens_is_pinhole(&cb.split[WS_TRAIN].views[0].lens) && cb.split[WS_TRAIN].views[0].lens.k[0] == -0.25,
          "the lens is read");
    double photos, mean, cameras;
    CHECK(compare(&ns, &cb, &photos, &mean, &cameras) == 0 && photos <= 1.0 / 255 && cameras < 1e-9,
          "nerfstudio vs binary COLMAP: photos %g, cameras %g", photos, cameras);
    printf("nerfstudio vs binary COLMAP: photos %.3g, cameras %.3g\n", photos, cameras);
    CHECK(compare(&ns, &ct, &photos, &mean, &cameras) == 0 && photos <= 1.0 / 255 && cameras < 1e-9,
          "nerfstudio vs text COLMAP: photos %g, cameras %g", photos, cameras);
    printf("nerfstudio vs text COLMAP: photos %.3g, cameras %.3g\n", photos, cameras);
    /* JPEG at quality 95: a few grey levels at the edges, under one on average */
    CHECK(compare(&cb, &cj, &photos, &mean, &cameras) == 0 && mean < 1.0 / 255 && photos < 0.25 &&
              cameras < 1e-9,
          "JPEG vs PNG: photos max %g mean %g, cameras %g", photos, mean, cameras);
    printf("JPEG vs PNG: max %.4f mean %.5f\n", photos, mean);
    /* nerfstudio's file_path "rgb/train/r_0.jpg" is used as written */
    CHECK(compare(&nj, &cj, &photos, &mean, &cameras) == 0 && photos == 0 && cameras < 1e-9,
          "nerfstudio JPEG vs COLMAP JPEG: photos %g, cameras %g", photos, cameras);
    ws_scene moved;
    char out2[2000], images[400], dir[400];
    snprintf(images, sizeof images, "%s/elsewhere", tmp);
    snprintf(dir, sizeof dir, "%s/cb", tmp);
    run_cmd(out2, sizeof out2, "mv %s/images %s", dir, images);
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 48;
    so.images_dir = images;
    if (!ws_scene_load(&moved, dir, &so, &st)) {
        CHECK(compare(&moved, &cb, &photos, &mean, &cameras) == 0 && photos == 0 && cameras == 0,
              "--images: photos %g, cameras %g", photos, cameras);
        ws_scene_free(&moved);
    } else {
        CHECK(0, "--images: %s", st.msg);
    }
    run_cmd(out2, sizeof out2, "mv %s %s/images", images, dir);
    /* undistortion undoes the lens: the pinhole scene's photos, up to the
     * two bilinear resamplings (render -> lens -> pinhole) at edges */
    CHECK(compare(&ns, &pin, &photos, &mean, &cameras) == 0 && mean < 1.0 / 255 && cameras < 1e-9,
          "lens vs pinhole: photos max %g mean %g, cameras %g", photos, mean, cameras);
    printf("lens undone vs pinhole: max %.4f mean %.5f\n", photos, mean);
    int n, m;
    const double *points = ws_scene_points(&cb, &n), *ply = ws_scene_points(&ns, &m);
    double worst = n == m && points && ply ? 0 : INFINITY;
    for (int k = 0; k < 3 * n && n == m && points && ply; k++) worst = fmax(worst, fabs(points[k] - ply[k]));
    CHECK(n == 2000 && worst == 0, "the sparse points: %d in points3D.bin, %d in sparse_pc.ply, %g apart", n, m,
          worst);
    ws_scene_free(&ns);
    ws_scene_free(&cb);
    ws_scene_free(&ct);
    ws_scene_free(&cj);
    ws_scene_free(&nj);
    ws_scene_free(&pin);
}

/* A 16 x 8 JPEG written by libjpeg directly: CMYK, or progressive RGB. */
static void write_special_jpeg(const char *path, int cmyk, int progressive) {
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    FILE *f = fopen(path, "wb");
    jpeg_stdio_dest(&c, f);
    c.image_width = 16;
    c.image_height = 8;
    c.input_components = cmyk ? 4 : 3;
    c.in_color_space = cmyk ? JCS_CMYK : JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 100, TRUE);
    if (progressive) jpeg_simple_progression(&c);
    jpeg_start_compress(&c, TRUE);
    unsigned char row[16 * 4];
    while (c.next_scanline < 8) {
        for (int j = 0; j < 16 * c.input_components; j++) row[j] = (unsigned char)(j * 4 + c.next_scanline * 16);
        JSAMPROW r = row;
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    fclose(f);
}

static void test_jpeg(void) {
    char path[400], want[600];
    static const float black[3] = {0, 0, 0};
    ws_image a, b;
    ws_status st;
    snprintf(path, sizeof path, "%s/cmyk.jpg", tmp);
    write_special_jpeg(path, 1, 0);
    snprintf(want, sizeof want, "%s: CMYK JPEG is not supported (convert it to RGB)", path);
    CHECK(ws_image_read(path, 0, 0, black, &a, &st) == WS_EINPUT && !strcmp(st.msg, want), "CMYK: %s", st.msg);
    snprintf(path, sizeof path, "%s/progressive.jpg", tmp);
    write_special_jpeg(path, 0, 1);
    char base[400];
    snprintf(base, sizeof base, "%s/baseline.jpg", tmp);
    write_special_jpeg(base, 0, 0);
    if (ws_image_read(path, 0, 0, black, &a, &st) || ws_image_read(base, 0, 0, black, &b, &st)) {
        CHECK(0, "progressive: %s", st.msg);
        return;
    }
    CHECK(a.width == 16 && a.height == 8 && max_diff(&a, &b, NULL) <= 1.0 / 255,
          "progressive as baseline: %g", max_diff(&a, &b, NULL));
    ws_image_free(&a);
    ws_image_free(&b);
    /* the size limit is PNG's: a header claiming 40000 x 40000 is refused
     * before anything that size is allocated (SOF0: FF C0, length,
     * precision, height, width) */
    FILE *f = fopen(base, "rb");
    unsigned char bytes[4096];
    size_t n = f ? fread(bytes, 1, sizeof bytes, f) : 0;
    if (f) fclose(f);
    for (size_t i = 0; i + 9 < n; i++)
        if (bytes[i] == 0xFF && bytes[i + 1] == 0xC0) {
            bytes[i + 5] = bytes[i + 7] = 40000 >> 8;
            bytes[i + 6] = bytes[i + 8] = 40000 & 255;
            break;
        }
    snprintf(path, sizeof path, "%s/huge.jpg", tmp);
    f = fopen(path, "wb");
    if (f) {
        fwrite(bytes, 1, n, f);
        fclose(f);
    }
    snprintf(want, sizeof want, "%s: image too large (40000 x 40000 pixels)", path);
    CHECK(ws_image_read(path, 0, 0, black, &a, &st) == WS_EINPUT && !strcmp(st.msg, want),
          "too large: %s", st.msg);
    /* a cut file: libjpeg's warning is an error, not grey rows */
    char out[1000];
    run_cmd(out, sizeof out, "head -c 300 %s > %s/cut.jpg", base, tmp);
    snprintf(path, sizeof path, "%s/cut.jpg", tmp);
    snprintf(want, sizeof want, "%s: truncated or corrupt JPEG (Premature end of JPEG file)", path);
    CHECK(ws_image_read(path, 0, 0, black, &a, &st) == WS_EINPUT && !strcmp(st.msg, want),
          "truncated: %s", st.msg);
}

/* View v's working image (48 x 48) from the file at path (its photo or
 * its mask) decoded whole, as the loader makes it from a file it does not
 * decode smaller (io/scene.c to_view_crop at the file's scale): undistorted
 * through its lens over its crop, or cropped, then averaged down; black
 * where the photo has nothing. */
static int whole_working(const ws_view *v, const char *path, ws_image *out, ws_status *st) {
    static const float black[3] = {0, 0, 0};
    ws_image whole = {0}, part = {0};
    const double rect[4] = {v->crop[0], v->crop[1], v->crop[2], v->crop[3]};
    int rc = ws_image_read(path, 0, 0, black, &whole, st);
    if (!rc)
        rc = ws_lens_is_pinhole(&v->lens)
                 ? ws_image_crop(&whole, v->crop[0], v->crop[1], v->crop[2], v->crop[3], &part, st)
                 : ws_image_undistort(&whole, 1.0, &v->lens, black, rect, v->crop[2], v->crop[3], &part, st);
    if (!rc) rc = ws_image_resample(&part, 48, 48, out, st);
    ws_image_free(&whole);
    ws_image_free(&part);
    return rc;
}

/* Scene `png_name` (640 x 480 PNG photos) and its JPEG twin `jpeg_name`,
 * loaded at a working size of 48 and so decoded at a half, against the
 * PNG's photos decoded whole (whole_working). */
static void compare_reduced(const char *png_name, const char *jpeg_name, const char *what) {
    ws_status st;
    ws_scene png, jpeg;
    if (load(&png, png_name, &st) || load(&jpeg, jpeg_name, &st)) {
        CHECK(0, "%sloading the large scenes: %s", what, st.msg);
        return;
    }
    double worst[2] = {0, 0}, sum[2] = {0, 0}, cameras = 0;
    size_t n = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < png.split[s].n && k < jpeg.split[s].n; k++) {
            const ws_view *a = &png.split[s].views[k], *b = &jpeg.split[s].views[k];
            ws_image whole;
            if (whole_working(a, a->image_path, &whole, &st)) {
                CHECK(0, "%s%s decoded whole: %s", what, a->image_path, st.msg);
                continue;
            }
            for (size_t p = 0; p < (size_t)3 * 48 * 48; p++)
                for (int t = 0; t < 2; t++) {
                    const double d = fabs((double)(t ? b : a)->photo.data[p] - whole.data[p]);
                    worst[t] = fmax(worst[t], d);
                    sum[t] += d;
                }
            n += 3 * 48 * 48;
            cameras = fmax(cameras, camera_diff(&a->cam, &b->cam));
            ws_image_free(&whole);
        }
    const char *names[2] = {"PNG", "JPEG"};
    for (int t = 0; t < 2; t++) {
        const double mean = n ? sum[t] / n : 1;
        CHECK(n == 4 * 3 * 48 * 48 && mean < 1.0 / 255 && worst[t] < 0.25 && cameras < 1e-9,
              "%sa half's %s vs the whole PNG: photos max %g mean %g over %zu values, cameras %g", what, names[t],
              worst[t], mean, n, cameras);
        printf("%sa half's %s vs the whole PNG: max %.4f mean %.5f\n", what, names[t], worst[t], mean);
    }
    char line[1024], line_png[1024];
    ws_scene_crop_line(&jpeg, line, sizeof line);
    ws_scene_crop_line(&png, line_png, sizeof line_png);
    static const char *said = "; 4 of 4 photos decoded at 1/2 of their size, the pixels the working views need";
    CHECK(strstr(line, said) && strstr(line_png, said), "%sthe crop line says so: %s / %s", what, line, line_png);
    ws_scene_free(&png);
    ws_scene_free(&jpeg);
}

/* A large photo is decoded smaller where its view needs fewer pixels
 * (image.h ws_image_read_reduced): a 640 x 480 capture through a lens,
 * loaded at a working size of 48, is decoded at a half a side, JPEG and
 * PNG alike, and its working photos are those the PNG gives decoded
 * whole, within what JPEG itself changes (test_formats), as are those of
 * a pinhole twin; the 16
 * x 8 baseline file at a half is 8 x 4 and names its own size, and the
 * PNG at a quarter is 160 x 120 (its blocks' means: test_scene); a view's
 * mask is decoded at its photo's half, and its working mask is the one
 * the mask decoded whole gives. */
static void test_reduced(void) {
    static const float black[3] = {0, 0, 0};
    char path[400];
    ws_image whole, half;
    ws_status st;
    int reduced, file_size[2];
    snprintf(path, sizeof path, "%s/baseline.jpg", tmp);
    if (ws_image_read(path, 0, 0, black, &whole, &st) ||
        ws_image_read_reduced(path, 2, black, &half, NULL, &reduced, file_size, &st)) {
        CHECK(0, "reduced: %s", st.msg);
        return;
    }
    CHECK(reduced == 2 && half.width == 8 && half.height == 4 && file_size[0] == 16 && file_size[1] == 8,
          "at a half: %d x %d, factor %d, file %d x %d", half.width, half.height, reduced, file_size[0],
          file_size[1]);
    ws_image_free(&whole);
    ws_image_free(&half);
    char out[4096];
    int rc = run_cmd(out, sizeof out,
                     "cd %s && %s scene cube --width 640 --height 480 --views-train 2 --views-val 1 --views-test 1 "
                     LENS " --layout colmap --out big_png && %s scene cube --width 640 --height 480 --views-train 2 "
                     "--views-val 1 --views-test 1 " LENS " --layout colmap --jpeg --out big_jpeg && "
                     "%s scene cube --width 640 --height 480 --views-train 2 --views-val 1 --views-test 1 "
                     "--layout nerfstudio --out big_pin_png && %s scene cube --width 640 --height 480 "
                     "--views-train 2 --views-val 1 --views-test 1 --layout nerfstudio --jpeg --out big_pin_jpeg",
                     tmp, bin, bin, bin, bin);
    CHECK(rc == 0, "large scenes: %s", out);
    snprintf(path, sizeof path, "%s/big_png/images/train/r_00000.png", tmp);
    CHECK(!ws_image_read_reduced(path, 4, black, &whole, NULL, &reduced, file_size, &st) && reduced == 4 &&
              whole.width == 160 && whole.height == 120 && file_size[0] == 640 && file_size[1] == 480,
          "a PNG at a quarter: factor %d, %d x %d", reduced, whole.width, whole.height);
    ws_image_free(&whole);
    compare_reduced("big_png", "big_jpeg", "");
    /* without a lens the crop is sampled from the smaller photo the same way */
    compare_reduced("big_pin_png", "big_pin_jpeg", "pinhole, ");
    /* a mask is decoded at its photo's scale: the working masks are those
     * of the masks decoded whole but where a block straddles the outline */
    rc = run_cmd(out, sizeof out,
                 "cd %s && %s scene cube --width 640 --height 480 --views-train 2 --views-val 1 --views-test 1 " LENS
                 " --layout colmap --masks --out big_masks",
                 tmp, bin);
    CHECK(rc == 0, "a large scene with masks: %s", out);
    ws_scene masked;
    if (load(&masked, "big_masks", &st)) {
        CHECK(0, "loading the large scene with masks: %s", st.msg);
        return;
    }
    int differ = 0, object = 0, views = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < masked.split[s].n; k++) {
            const ws_view *v = &masked.split[s].views[k];
            ws_image whole;
            if (!v->mask.data || v->reduced != 2 || whole_working(v, v->mask_path, &whole, &st)) continue;
            views++;
            for (int p = 0; p < 48 * 48; p++) {
                object += v->mask.data[p] > 0.5f;
                differ += (v->mask.data[p] > 0.5f) != (whole.data[p] >= 0.5f);
            }
            ws_image_free(&whole);
        }
    CHECK(views == 4 && object > 1000 && differ <= object / 50,
          "masks at a half: %d of %d views, %d of %d object pixels differ from the masks decoded whole", views, 4,
          differ, object);
    printf("masks at a half: %d of %d object pixels differ from the masks decoded whole\n", differ, object);
    ws_scene_free(&masked);
}

static void test_refusals(void) {
    char out[1 << 14];
    /* each from a fresh copy of the text or binary COLMAP scene */
    static const struct {
        const char *from, *edit, *msg;
    } cases[] = {
        {"ct", "sed -i 's/ OPENCV / FOV /' sparse/0/cameras.txt",
         "T/bad/sparse/0/cameras.txt: line 3: camera 1: unknown camera model 'FOV' (SIMPLE_PINHOLE, PINHOLE, "
         "SIMPLE_RADIAL, RADIAL, OPENCV, OPENCV_FISHEYE or FULL_OPENCV)"},
        {"ct", "rm images/train/r_00002.jpg images/train/r_00002.png 2>/dev/null; true",
         "T/bad/sparse/0/images.txt: image 3: no file T/bad/images/train/r_00002.png"},
        {"ct", "sed -i '9s/^7 [^ ]*/7 nan/' sparse/0/points3D.txt",
         "T/bad/sparse/0/points3D.txt: line 9: point 7: coordinate is not finite"},
        {"cb", "head -c 600 sparse/0/images.bin > x && mv x sparse/0/images.bin",
         "T/bad/sparse/0/images.bin: truncated (ends inside image 7 of 8)"},
        {"cb", "head -c 200 sparse/0/images.bin > x && mv x sparse/0/images.bin",
         "T/bad/sparse/0/images.bin: truncated (8 images do not fit in its 200 bytes)"},
        {"cb", "head -c 100 sparse/0/points3D.bin > x && mv x sparse/0/points3D.bin",
         "T/bad/sparse/0/points3D.bin: truncated (2000 points do not fit in its 100 bytes)"},
        {"ns", "sed -i 's/\"ply_file_path\":[^,]*,/\"ply_file_path\": 7,/' transforms.json",
         "T/bad/transforms.json: ply_file_path is not a file name"},
        {"ns", "sed -i '9s/^[^ ]*/nan/' sparse_pc.ply", "T/bad/sparse_pc.ply: vertex row 1 has a non-finite coordinate"},
        {"ns", "sed -i 's|\"ply_file_path\":[^,]*,|\"ply_file_path\": \"../ns/sparse_pc.ply\",|' transforms.json",
         "T/bad/transforms.json: ply_file_path '../ns/sparse_pc.ply' leaves the scene directory ('..')"},
        {"ct", "sed -i 's/ -0.25 [^ ]* / -0.9 0 /' sparse/0/cameras.txt",
         "T/bad/sparse/0/cameras.txt: line 3: camera 1: lens distortion folds the image (the "
         "distorted radius stops growing at 34 px from the principal point, inside the frame, whose "
         "corner is 50 px out)"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int rc = run_cmd(out, sizeof out, "cd %s && rm -rf bad && cp -r %s bad && cd bad && %s", tmp,
                         cases[k].from, cases[k].edit);
        CHECK(rc == 0, "case %zu: edit: %s", k, out);
        const char *msg = load_error("bad");
        CHECK(!strcmp(msg, cases[k].msg), "case %zu:\n  got  %s\n  want %s", k, msg, cases[k].msg);
    }
    int rc = run_cmd(out, sizeof out, "%s scene cube " SCENE_ARGS " --lens -0.9,0,0,0 --layout colmap --out %s/fold",
                     bin, tmp);
    CHECK(rc == 2 || rc == 1, "folding --lens refused: %d", rc);
    CHECK(strstr(out, "wiresketch: --lens: lens distortion folds the image (the distorted radius "
                      "stops growing at 34 px from the principal point, inside the frame, whose "
                      "corner is 50 px out)") != NULL,
          "fold message: %s", out);
}

/* The extent in working pixels (the larger of width and height) of the
 * object's points in view v, and the least distance of any of them to the
 * view's border (negative: one is outside). */
static void object_in_view(const ws_view *v, const ws_pointcloud *pc, int size, double *extent, double *inside) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    *inside = INFINITY;
    for (int k = 0; k < pc->n; k++) {
        double c[3], uv[2];
        ws_camera_to_cam(&v->cam, &pc->xyz[3 * k], c);
        ws_camera_project(&v->cam, c, &uv[0], &uv[1]);
        for (int i = 0; i < 2; i++) {
            lo[i] = fmin(lo[i], uv[i]), hi[i] = fmax(hi[i], uv[i]);
            *inside = fmin(*inside, fmin(uv[i], size - uv[i]));
        }
    }
    *extent = fmax(hi[0] - lo[0], hi[1] - lo[1]);
}

static void test_zoom(void) {
    char out[4096], ns[300], cm[300], path[1024], line[2048];
    snprintf(ns, sizeof ns, "%s/zoom_ns", tmp);
    snprintf(cm, sizeof cm, "%s/zoom_colmap", tmp);
    int rc = run_cmd(out, sizeof out,
                     "%s scene cube --layout nerfstudio --width 192 --height 144 --fov 70 --background room "
                     "--views-train 6 --views-val 1 --views-test 1 --out %s && %s scene cube --layout colmap "
                     "--width 192 --height 144 --fov 70 --background room --views-train 6 --views-val 1 "
                     "--views-test 1 --out %s",
                     bin, ns, bin, cm);
    CHECK(rc == 0, "zoom scenes: %s", out);
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 48;
    ws_scene zoomed, twin, whole;
    ws_status st;
    ws_pointcloud pc = {0};
    snprintf(path, sizeof path, "%s/gt_points.ply", ns);
    if (rc || ws_pointcloud_load_ply(path, &pc, &st) || ws_roi_load_scene(&zoomed, ns, &so, NULL, NULL, NULL, &st)) {
        CHECK(0, "zoomed scene: %s", rc ? out : st.msg);
        ws_pointcloud_free(&pc);
        return;
    }
    CHECK(zoomed.zoomed == 8, "%d of 8 views zoomed", zoomed.zoomed);
    if (!ws_scene_load(&whole, ns, &so, &st)) {
        double worst_gain = INFINITY, worst_inside = INFINITY;
        int smallest = 144, largest = 0;
        for (int s = 0; s < WS_NSPLITS; s++)
            for (int k = 0; k < zoomed.split[s].n; k++) {
                const ws_view *z = &zoomed.split[s].views[k], *w = &whole.split[s].views[k];
                double ez, ew, iz, iw;
                object_in_view(z, &pc, 48, &ez, &iz);
                object_in_view(w, &pc, 48, &ew, &iw);
                worst_gain = fmin(worst_gain, ez / ew);
                worst_inside = fmin(worst_inside, iz);
                smallest = z->crop[2] < smallest ? z->crop[2] : smallest;
                largest = z->crop[2] > largest ? z->crop[2] : largest;
            }
        CHECK(worst_gain > 1.3, "the object is only %.2f times as large zoomed", worst_gain);
        CHECK(worst_inside > 0, "the object leaves a zoomed view by %.2f px", -worst_inside);
        CHECK(smallest >= 48 && largest < 144, "zoomed crops %d to %d px of a 144 px frame", smallest, largest);
        ws_scene_free(&whole);
    } else {
        CHECK(0, "whole scene: %s", st.msg);
    }
    if (!ws_roi_load_scene(&twin, cm, &so, NULL, NULL, NULL, &st)) {
        double photos, mean, cameras;
        int same = compare(&zoomed, &twin, &photos, &mean, &cameras) == 0;
        for (int s = 0; s < WS_NSPLITS && same; s++)
            for (int k = 0; k < zoomed.split[s].n; k++)
                same &= !memcmp(zoomed.split[s].views[k].crop, twin.split[s].views[k].crop, sizeof(int[4]));
        CHECK(same && cameras < 1e-9 && photos <= 1.0 / 255 + 1e-6,
              "the COLMAP twin zooms the same way: crops %s, cameras %g, photos %g", same ? "equal" : "differ",
              cameras, photos);
        ws_scene_free(&twin);
    } else {
        CHECK(0, "COLMAP twin: %s", st.msg);
    }
    ws_scene_crop_line(&zoomed, line, sizeof line);
    snprintf(path, sizeof path, "%s: the working views are crops of their frames zoomed onto the region of interest "
             "(8 of 8 views zoomed, ", ns);
    CHECK(!strncmp(line, path, strlen(path)), "crop line: %s", line);
    ws_scene_free(&zoomed);
    ws_pointcloud_free(&pc);
}

int main(void) {
    char cwd[256]; /* the scenes are made from inside tmp */
    if (program_path()[0] != '/' && getcwd(cwd, sizeof cwd))
        snprintf(bin, sizeof bin, "%.255s/%.700s", cwd, program_path());
    else
        snprintf(bin, sizeof bin, "%s", program_path());
    tmp = test_tmpdir("capture");
    test_formats();
    test_jpeg();
    test_reduced();
    test_refusals();
    test_zoom();
    return check_summary();
}
