/* test_nerfstudio.c: scenes in the nerfstudio / instant-ngp layout (one
 * transforms.json with intrinsics; scene.h), written by the program itself:
 * - the twin test: a 96 x 64 nerfstudio scene and the 64 x 64 NeRF-synthetic
 *   scene of the same cameras load into the same working photos and cameras
 *   (to float tolerance) and give the same `grad` output;
 * - per-frame intrinsics, an off-centre principal point and fl_x != fl_y:
 *   the crop and the camera against the formulas of scene_nerfstudio.c;
 * - the split rule of a file without split lists;
 * - every refusal (folding lens, distortion on a pinhole or tangential on a
 *   fisheye model, unknown camera model, missing w, wrong image size)
 *   with its exact message;
 * - --background: white, auto (border median), R,G,B, and a mask_path
 *   that sets the background. */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "io/scene.h"
#include "scene_load.h"

static const char *bin, *tmp;

static double max_diff(const ws_image *a, const ws_image *b) {
    if (a->width != b->width || a->height != b->height || a->channels != b->channels) return INFINITY;
    double worst = 0;
    for (size_t k = 0; k < (size_t)a->width * a->height * a->channels; k++)
        worst = fmax(worst, fabs(a->data[k] - b->data[k]));
    return worst;
}

static double camera_diff(const ws_camera *a, const ws_camera *b) {
    double worst = fabs(a->focal - b->focal) + fabs(a->cx - b->cx) + fabs(a->cy - b->cy);
    for (int i = 0; i < 3; i++) {
        worst = fmax(worst, fabs(a->t[i] - b->t[i]));
        for (int j = 0; j < 3; j++) worst = fmax(worst, fabs(a->R[i][j] - b->R[i][j]));
    }
    return worst + abs(a->width - b->width) + abs(a->height - b->height);
}

static void test_twin(void) {
    char out[1 << 16], ns[400], nf[400];
    snprintf(ns, sizeof ns, "%s/ns", tmp);
    snprintf(nf, sizeof nf, "%s/nf", tmp);
    int rc = run_cmd(out, sizeof out,
                     "%s scene trefoil --layout nerfstudio --width 96 --height 64 --views-train 6 "
                     "--views-val 2 --views-test 3 --out %s && %s scene trefoil --size 64 --views-train 6 "
                     "--views-val 2 --views-test 3 --out %s && rm %s/sparse_pc.ply",
                     bin, ns, bin, nf, ns);
    CHECK(rc == 0, "scenes: %s", out);
    ws_scene a, b;
    ws_status st;
    /* 48: the crop is resampled too. Without its sparse points the
     * nerfstudio twin's views are not zoomed (geometry/roi.h), and so
     * are its twin's whole frames. */
    if (load_scene_at(&a, ns, 48, &st)) {
        CHECK(0, "nerfstudio twin: %s", st.msg);
        return;
    }
    CHECK(a.layout == WS_LAYOUT_NERFSTUDIO, "layout detected");
    if (load_scene_at(&b, nf, 48, &st)) {
        CHECK(0, "nerf twin: %s", st.msg);
        ws_scene_free(&a);
        return;
    }
    double photos = 0, cameras = 0;
    int same_counts = 1;
    for (int s = 0; s < WS_NSPLITS; s++) {
        same_counts &= a.split[s].n == b.split[s].n;
        for (int k = 0; k < a.split[s].n && same_counts; k++) {
            photos = fmax(photos, max_diff(&a.split[s].views[k].photo, &b.split[s].views[k].photo));
            cameras = fmax(cameras, camera_diff(&a.split[s].views[k].cam, &b.split[s].views[k].cam));
        }
    }
    CHECK(same_counts && a.split[WS_TRAIN].n == 6 && a.split[WS_TEST].n == 3, "twin split sizes");
    CHECK(photos < 1e-6, "twin working photos differ by %g", photos);
    CHECK(cameras < 1e-9, "twin cameras differ by %g", cameras);
    CHECK(fabs(a.camera_angle_x - b.camera_angle_x) < 1e-9, "twin angle %.17g vs %.17g", a.camera_angle_x,
          b.camera_angle_x);
    ws_scene_free(&a);
    ws_scene_free(&b);
    /* grad prints the same loss and gradient */
    static char ga[1 << 16], gb[1 << 16];
    const char *grad = "%s grad %s --curves %s/gt_curves.json --split test --view 1 --loss edges --size 48";
    int ra = run_cmd(ga, sizeof ga, grad, bin, ns, nf);
    int rb = run_cmd(gb, sizeof gb, grad, bin, nf, nf);
    cJSON *ja = cJSON_Parse(ga), *jb = cJSON_Parse(gb);
    double worst = INFINITY, scale = 0;
    if (ja && jb) {
        worst = fabs(cJSON_GetObjectItem(ja, "loss")->valuedouble - cJSON_GetObjectItem(jb, "loss")->valuedouble);
        const cJSON *x = cJSON_GetObjectItem(ja, "grad"), *y = cJSON_GetObjectItem(jb, "grad");
        for (int c = 0; c < cJSON_GetArraySize(x); c++)
            for (int j = 0; j < 4; j++)
                for (int d = 0; d < 3; d++) {
                    double u = cJSON_GetArrayItem(cJSON_GetArrayItem(cJSON_GetArrayItem(x, c), j), d)->valuedouble;
                    double v = cJSON_GetArrayItem(cJSON_GetArrayItem(cJSON_GetArrayItem(y, c), j), d)->valuedouble;
                    worst = fmax(worst, fabs(u - v));
                    scale = fmax(scale, fabs(v));
                }
    }
    CHECK(ra == 0 && rb == 0 && worst <= 1e-6 * scale && scale > 0,
          "twin grad differs by %g (largest %g): %.200s", worst, scale, ra ? ga : gb);
    cJSON_Delete(ja);
    cJSON_Delete(jb);
}

/* Writes DIR/transforms.json: `global` (JSON members) and frames whose
 * members are frames[k], each with the twin's image train/r_K and camera. */
static void write_scene(const char *name, const char *global, int n, const char *const *frames) {
    char path[600], twin[600], *text = malloc(1 << 20);
    snprintf(path, sizeof path, "%s/%s", tmp, name);
    snprintf(twin, sizeof twin, "%s/ns", tmp);
    char cmd[2000];
    snprintf(cmd, sizeof cmd, "mkdir -p %s && cp -r %s/rgb %s/", path, twin, path);
    if (system(cmd)) exit(1);
    ws_status st;
    ws_scene sc;
    if (load_scene_at(&sc, twin, 48, &st)) exit(1);
    int len = sprintf(text, "{%s%s\"frames\": [", global, *global ? ", " : "");
    for (int k = 0; k < n; k++) {
        const ws_camera *cam = &sc.split[WS_TRAIN].views[k % 6].cam;
        len += sprintf(text + len, "%s{\"file_path\": \"rgb/train/r_%d.png\", %s%s\"transform_matrix\": [", k ? ", " : "",
                       k % 6, frames ? frames[k] : "", frames && *frames[k] ? ", " : "");
        for (int i = 0; i < 4; i++)
            len += sprintf(text + len, "%s[%.17g, %.17g, %.17g, %.17g]", i ? ", " : "", cam->c2w[i][0],
                           cam->c2w[i][1], cam->c2w[i][2], cam->c2w[i][3]);
        len += sprintf(text + len, "]}");
    }
    sprintf(text + len, "]}\n");
    ws_scene_free(&sc);
    strcat(path, "/transforms.json");
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    free(text);
}

static void test_intrinsics(void) {
    /* frame 1 has its own focal lengths and principal point */
    const char *frames[2] = {"", "\"fl_x\": 100, \"fl_y\": 110, \"cx\": 50, \"cy\": 30"};
    write_scene("intr", "\"fl_x\": 80, \"w\": 96, \"h\": 64, \"k1\": 0, \"camera_model\": \"OPENCV\"", 2, frames);
    char dir[400];
    snprintf(dir, sizeof dir, "%s/intr", tmp);
    ws_scene sc;
    ws_status st;
    if (load_scene_at(&sc, dir, 48, &st)) {
        CHECK(0, "intrinsics scene: %s", st.msg);
        return;
    }
    /* no split lists: frame 0 is test, frame 1 train */
    CHECK(sc.split[WS_TEST].n == 1 && sc.split[WS_TRAIN].n == 1 && sc.split[WS_VAL].n == 0,
          "split rule on 2 frames: %d %d %d", sc.split[0].n, sc.split[1].n, sc.split[2].n);
    /* frame 0: fl 80 both ways, cx 48, cy 32: the centred 64 x 64 square */
    const ws_view *t = &sc.split[WS_TEST].views[0], *v = &sc.split[WS_TRAIN].views[0];
    CHECK(t->crop[0] == 16 && t->crop[1] == 0 && t->crop[2] == 64 && t->crop[3] == 64, "square crop");
    CHECK(fabs(t->cam.focal - 80 * 0.75) < 1e-12 && fabs(t->cam.cx - 24) < 1e-12 && fabs(t->cam.cy - 24) < 1e-12,
          "square camera %g %g %g", t->cam.focal, t->cam.cx, t->cam.cy);
    /* frame 1: aspect 100/110 -> 58 x 64 around the object's projection,
     * its principal point (its camera looks at the scene centre): x0 = 50 - 29 */
    double sx = 48.0 / 58, sy = 48.0 / 64;
    CHECK(v->crop[0] == 21 && v->crop[1] == 0 && v->crop[2] == 58 && v->crop[3] == 64, "crop %d %d %d %d",
          v->crop[0], v->crop[1], v->crop[2], v->crop[3]);
    CHECK(fabs(v->cam.focal - sqrt(100 * sx * 110 * sy)) < 1e-12 && fabs(v->cam.cx - 29 * sx) < 1e-12 &&
              fabs(v->cam.cy - 30 * sy) < 1e-12,
          "camera %g %g %g", v->cam.focal, v->cam.cx, v->cam.cy);
    CHECK(fabs(100 * sx / (110 * sy) - 1) < 0.5 / 58, "square pixels to half a crop pixel");
    CHECK(v->photo.width == 48 && v->photo.height == 48, "working size");
    ws_scene_free(&sc);

    /* ten frames, no lists: test 0 and 8, val 4 */
    write_scene("ten", "\"fl_x\": 80, \"w\": 96, \"h\": 64", 10, NULL);
    snprintf(dir, sizeof dir, "%s/ten", tmp);
    if (!load_scene_at(&sc, dir, 32, &st)) {
        CHECK(sc.split[WS_TRAIN].n == 7 && sc.split[WS_VAL].n == 1 && sc.split[WS_TEST].n == 2,
              "split rule on 10 frames: %d %d %d", sc.split[0].n, sc.split[1].n, sc.split[2].n);
        ws_scene_free(&sc);
    } else {
        CHECK(0, "ten: %s", st.msg);
    }
}

static void test_refusals(void) {
    static const struct {
        const char *global, *frame0, *msg;
    } cases[] = {
        {"\"fl_x\": 80, \"w\": 96, \"h\": 64, \"k1\": -0.9", "",
         "frame 0: lens distortion folds the image (the distorted radius stops growing at 32 px from "
         "the principal point, inside the frame, whose corner is 58 px out)"},
        {"\"fl_x\": 80, \"w\": 96, \"h\": 64, \"camera_model\": \"PINHOLE\"", "\"p2\": -0.001",
         "frame 0: distortion p2 = -0.001 with camera_model PINHOLE (a lens with distortion is OPENCV "
         "or OPENCV_FISHEYE)"},
        {"\"fl_x\": 80, \"w\": 96, \"h\": 64, \"camera_model\": \"EQUIRECTANGULAR\"", "",
         "frame 0: camera_model is not PINHOLE, SIMPLE_PINHOLE, OPENCV or OPENCV_FISHEYE"},
        {"\"fl_x\": 80, \"w\": 96, \"h\": 64, \"is_fisheye\": true", "\"p1\": 0.01",
         "frame 0: distortion p1 = 0.01 with a fisheye lens (it has k1..k4 only)"},
        {"\"fl_x\": 80, \"h\": 64", "", "frame 0: missing w"},
        {"\"w\": 96, \"h\": 64", "", "frame 0: missing fl_x (or camera_angle_x)"},
        {"\"fl_x\": 80, \"w\": 96, \"h\": 64", "\"fl_y\": \"x\"", "frame 0: fl_y is not a finite number"},
        {"\"fl_x\": 80, \"w\": 100, \"h\": 64", "", "rgb/train/r_1.png: image is 96 x 64 but the scene file says w x h = 100 x 64"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char *frames[2] = {cases[k].frame0, ""};
        write_scene("bad", cases[k].global, 2, frames);
        char dir[400];
        snprintf(dir, sizeof dir, "%s/bad", tmp);
        ws_scene sc;
        ws_status st;
        int rc = load_scene_at(&sc, dir, 32, &st);
        CHECK(rc == WS_EINPUT && strstr(st.msg, cases[k].msg) && !strncmp(st.msg, dir, strlen(dir)),
              "case %zu: rc %d: %s", k, rc, st.msg);
        if (!rc) ws_scene_free(&sc);
    }
}

static float corner(const ws_scene *sc, int c) {
    const ws_image *p = &sc->split[WS_TRAIN].views[0].photo;
    return p->data[(size_t)c * p->width * p->height];
}

static void test_background(void) {
    char out[4096], dir[400];
    snprintf(dir, sizeof dir, "%s/white", tmp);
    int rc = run_cmd(out, sizeof out,
                     "%s scene trefoil --layout nerfstudio --width 64 --height 48 --background white "
                     "--views-train 2 --views-val 0 --views-test 1 --out %s",
                     bin, dir);
    CHECK(rc == 0, "white scene: %s", out);
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = opt.height = 32;
    ws_status st;
    ws_scene sc;
    opt.background_auto = 1;
    if (ws_scene_load(&sc, dir, &opt, &st) == WS_OK) {
        CHECK(corner(&sc, 0) == 1 && corner(&sc, 2) == 1, "white photo stays white");
        ws_scene_free(&sc);
    }
    /* a mask_path that calls everything background: auto gives the border
     * median (white), a colour gives that colour */
    char path[600];
    snprintf(path, sizeof path, "%s/transforms.json", dir);
    FILE *f = fopen(path, "r");
    static char text[1 << 16], edited[1 << 16];
    size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
    if (f) fclose(f);
    text[n] = '\0';
    char *at = strstr(text, "\"file_path\":");
    if (at) {
        snprintf(edited, sizeof edited, "%.*s\"mask_path\": \"black.png\", %s", (int)(at - text), text, at);
        f = fopen(path, "w");
        fputs(edited, f);
        fclose(f);
    }
    ws_image black; /* the size of its image, as a mask must be */
    snprintf(path, sizeof path, "%s/black.png", dir);
    if (ws_image_alloc(&black, 64, 48, 1, &st) == WS_OK) {
        memset(black.data, 0, sizeof(float) * 64 * 48);
        ws_png_write(path, &black, &st);
        ws_image_free(&black);
    }
    opt.background_auto = 0;
    opt.background[0] = 0.25f;
    opt.background[1] = 0.5f;
    opt.background[2] = 1.0f;
    if (ws_scene_load(&sc, dir, &opt, &st) == WS_OK) {
        const ws_image *p = &sc.split[WS_TRAIN].views[0].photo, *m = &sc.split[WS_TRAIN].views[0].mask;
        double worst = 0;
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 32 * 32; k++) worst = fmax(worst, fabs(p->data[c * 32 * 32 + k] - opt.background[c]));
        CHECK(worst < 1e-6 && m->data && m->data[0] == 0, "masked-out photo is the background: %g", worst);
        CHECK(sc.split[WS_TRAIN].views[1].mask.data == NULL, "frame without mask_path: none");
        ws_scene_free(&sc);
    } else {
        CHECK(0, "mask_path scene: %s", st.msg);
    }
    /* the option as the commands read it */
    rc = run_cmd(out, sizeof out, "%s grad %s --curves %s/gt_curves.json --loss edges --background pink", bin, dir, dir);
    CHECK(rc == 2 && strstr(out, "wiresketch: --background: 'pink' is not black, white, auto or R,G,B in [0, 1]"),
          "--background pink: %s", out);
    rc = run_cmd(out, sizeof out, "%s grad %s --curves %s/gt_curves.json --loss edges --background 0.2,0.3,0.9 --size 32", bin, dir, dir);
    CHECK(rc == 0, "--background R,G,B: %s", out);
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("nerfstudio");
    test_twin();
    test_intrinsics();
    test_refusals();
    test_background();
    return check_summary();
}
