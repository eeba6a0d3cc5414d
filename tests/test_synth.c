/* test_synth.c: the synthetic scenes: they load as scenes, their images
 * show the ground-truth curves where the cameras project them (and nothing
 * elsewhere), the object is centred, gt_curves.json loads, and the same
 * options give the same bytes; the wire objects have their promised shapes.
 * Small scenes (few views, 64 to 96 px) keep it fast. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "render/curves.h"
#include "io/scene.h"
#include "synth/room.h"
#include "synth/solids.h"
#include "synth/synth.h"
#include "io/pointcloud.h"
#include "metrics/metrics.h"

static const char *tmp;

/* Checks one loaded view against the ground truth: every pixel on a
 * projected curve point is lit, every pixel farther than the tube's
 * projected radius + 1.5 px from all of them is black. */
static void check_view(const ws_view *v, const ws_curves *gt, const char *label) {
    const ws_image *im = &v->photo;
    const int W = im->width, H = im->height, S = 96;
    int n = gt->n * S, lit_on = 0, inside = 0, stray = 0, nonzero = 0;
    double *uvr = malloc(sizeof *uvr * 3 * n), maxv = 0;
    for (int ci = 0; ci < gt->n; ci++)
        for (int k = 0; k < S; k++) {
            double p[3], c[3];
            ws_curve_point(gt, ci, k / (S - 1.0), p);
            ws_camera_to_cam(&v->cam, p, c);
            double d = -c[2], *e = uvr + 3 * (ci * S + k);
            e[0] = W / 2.0 + v->cam.focal * c[0] / d;
            e[1] = H / 2.0 - v->cam.focal * c[1] / d;
            e[2] = v->cam.focal * gt->thickness / d;
            int j = (int)floor(e[0]), i = (int)floor(e[1]); /* pixel j spans [j, j+1) */
            if (i < 0 || j < 0 || i >= H || j >= W) continue;
            inside++;
            lit_on += im->data[i * W + j] + im->data[H * W + i * W + j] > 0.05;
        }
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            double sum = 0;
            for (int c = 0; c < 3; c++) {
                sum += im->data[(c * H + i) * W + j];
                maxv = fmax(maxv, im->data[(c * H + i) * W + j]);
            }
            nonzero += sum > 0;
            int far = 1;
            for (int k = 0; k < n && far; k++) {
                double du = j + 0.5 - uvr[3 * k], dv = i + 0.5 - uvr[3 * k + 1];
                far = du * du + dv * dv > (uvr[3 * k + 2] + 1.5) * (uvr[3 * k + 2] + 1.5);
            }
            stray += far && sum > 0;
        }
    CHECK(inside > n / 2 && lit_on == inside, "%s: %d of %d projected curve points lit", label,
          lit_on, inside);
    CHECK(stray == 0, "%s: %d lit pixels away from every tube", label, stray);
    CHECK(maxv > 0.3 && maxv < 0.99, "%s: brightest value %g (blank or saturated)", label, maxv);
    CHECK(nonzero > W * H / 100 && nonzero < W * H / 2, "%s: %d of %d pixels show the object",
          label, nonzero, W * H);
    free(uvr);
}

/* Generates `name` into tmp/dir_name and checks it end to end: its
 * gt_curves.json holds the object's `curves` curves. */
static void check_scene(const char *name, const char *dir_name, const int views[3], int size,
                        int curves) {
    char dir[512], path[600];
    snprintf(dir, sizeof dir, "%s/%s", tmp, dir_name);
    ws_status st;
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    memcpy(opt.views, views, sizeof opt.views);
    opt.size = size;
    opt.seed = 7;
    int rc = ws_synth_write(name, dir, &opt, &st);
    CHECK(rc == WS_OK, "%s: %s", name, st.msg);
    if (rc) return;

    ws_synth_object obj;
    rc = ws_synth_object_make(&obj, name, &st);
    CHECK(rc == WS_OK, "%s object: %s", name, st.msg);
    if (rc) return;
    ws_curves gt;
    snprintf(path, sizeof path, "%s/gt_curves.json", dir);
    rc = ws_curves_load(path, &gt, &st);
    CHECK(rc == WS_OK, "%s: %s", path, st.msg);
    if (rc) {
        ws_synth_object_free(&obj);
        return;
    }
    int same = gt.n == obj.curves.n && gt.thickness == obj.curves.thickness;
    for (int k = 0; same && k < gt.n * WS_CURVE_FLOATS; k++) same = gt.P[k] == obj.curves.P[k];
    CHECK(same, "%s: gt_curves.json holds the object's curves exactly", name);
    CHECK(gt.n == curves, "%s: %d curves in gt_curves.json, not %d", name, gt.n, curves);

    ws_scene sc;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = size;
    rc = ws_scene_load(&sc, dir, &so, &st);
    CHECK(rc == WS_OK, "%s load: %s", name, st.msg);
    if (!rc) {
        for (int s = 0; s < WS_NSPLITS; s++)
            CHECK(sc.split[s].n == views[s], "%s %s: %d views", name, ws_split_names[s],
                  sc.split[s].n);
        CHECK(fabs(sc.camera_angle_x - 2 * atan(18.0 / 50.0)) < 1e-15, "angle %.17g",
              sc.camera_angle_x);
        double off = 0;
        for (int i = 0; i < 3; i++)
            off += (sc.center[i] - obj.center[i]) * (sc.center[i] - obj.center[i]);
        CHECK(sqrt(off) < 1e-6, "%s: scene centre %g from the object's centre", name, sqrt(off));
        for (int s = 0; s < WS_NSPLITS; s++)
            for (int k = 0; k < sc.split[s].n; k++) {
                char label[700];
                snprintf(label, sizeof label, "%s %s/%s", name, ws_split_names[s],
                         sc.split[s].views[k].name);
                check_view(&sc.split[s].views[k], &gt, label);
                double pos[3], dist = 0;
                ws_camera_position(&sc.split[s].views[k].cam, pos);
                for (int i = 0; i < 3; i++)
                    dist += (pos[i] - obj.center[i]) * (pos[i] - obj.center[i]);
                CHECK(fabs(sqrt(dist) - 4.0) < 1e-9 && pos[2] > obj.center[2],
                      "%s: camera on the upper hemisphere of radius 4", label);
            }
        ws_scene_free(&sc);
    }
    for (int s = 1; s < WS_NSPLITS; s++) {
        snprintf(path, sizeof path, "%s/transforms_%s.json", dir, ws_split_names[s]);
        CHECK((access(path, F_OK) == 0) == (views[s] > 0), "%s: written iff the split has views",
              path);
    }
    ws_curves_free(&gt);
    ws_synth_object_free(&obj);
}

/* Two runs with the same options give the same bytes; another seed moves
 * the cameras. */
static void test_deterministic(void) {
    ws_status st;
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    opt.views[WS_TRAIN] = 4;
    opt.views[WS_VAL] = opt.views[WS_TEST] = 1;
    opt.size = 64;
    char a[512], b[512], c[512], pa[700], pb[700], pc[700];
    snprintf(a, sizeof a, "%s/run_a", tmp);
    snprintf(b, sizeof b, "%s/run_b", tmp);
    snprintf(c, sizeof c, "%s/run_c", tmp);
    int rc = ws_synth_write("chair", a, &opt, &st) || ws_synth_write("chair", b, &opt, &st);
    opt.seed = 99;
    rc = rc || ws_synth_write("chair", c, &opt, &st);
    CHECK(rc == 0, "runs: %s", st.msg);
    const char *files[] = {"transforms_train.json", "transforms_val.json", "transforms_test.json",
                           "gt_curves.json",        "rgb/train/r_0.png",   "rgb/train/r_3.png",
                           "rgb/val/r_0.png",       "rgb/test/r_0.png"};
    int differ = 0;
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        snprintf(pa, sizeof pa, "%s/%s", a, files[k]);
        snprintf(pb, sizeof pb, "%s/%s", b, files[k]);
        snprintf(pc, sizeof pc, "%s/%s", c, files[k]);
        CHECK(same_file(pa, pb), "%s differs between two identical runs", files[k]);
        differ += !same_file(pa, pc);
    }
    CHECK(differ >= 6, "another seed changed only %d files", differ);
    snprintf(pa, sizeof pa, "%s/gt_curves.json", a);
    snprintf(pc, sizeof pc, "%s/gt_curves.json", c);
    CHECK(same_file(pa, pc), "the ground truth does not depend on the seed");
}

static void test_errors(void) {
    ws_status st;
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    CHECK(opt.views[0] == 48 && opt.views[1] == 8 && opt.views[2] == 8 && opt.size == 224,
          "default options");
    char dir[512];
    snprintf(dir, sizeof dir, "%s/never", tmp);
    int rc = ws_synth_write("teapot", dir, &opt, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, "teapot: unknown synthetic scene (trefoil, chair, spring, flat, cube, "
                                    "dodecahedron, nut, bracket, torus, vase, animal)"),
          "unknown name: %s", st.msg);
    opt.colmap = 1;
    rc = ws_synth_write("vase", dir, &opt, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, "vase: --lens and --layout colmap are for the wire objects and solids"),
          "a smooth object as a COLMAP capture: %s", st.msg);
    opt.colmap = 0;
    opt.nerfstudio = 1;
    opt.lens[0] = -0.2;
    rc = ws_synth_write("torus", dir, &opt, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, "torus: --lens and --layout colmap are for the wire objects and solids"),
          "a smooth object through a lens: %s", st.msg);
    opt.lens[0] = 0;
    opt.nerfstudio = 0;
    opt.views[WS_TRAIN] = 0;
    rc = ws_synth_write("chair", dir, &opt, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, "--views-train: 0 is not in [1, 100000]"),
          "no train: %s", st.msg);
    opt.views[WS_TRAIN] = 2;
    opt.size = 4;
    rc = ws_synth_write("chair", dir, &opt, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, "--size: 4 is not in [8, 4096]"), "tiny size: %s",
          st.msg);
    CHECK(access(dir, F_OK) != 0, "nothing written on bad options");
    opt.size = 16;
    snprintf(dir, sizeof dir, "%s/no/such/parent", tmp);
    rc = ws_synth_write("chair", dir, &opt, &st);
    char want[700];
    snprintf(want, sizeof want, "%s: cannot create directory: No such file or directory", dir);
    CHECK(rc == WS_EIO && !strcmp(st.msg, want), "missing parent: %s", st.msg);
}

/* A solid scene: gt_curves.json holds its edges (count given), gt_points.ply
 * loads, the background is the chosen colour, and the object's outline
 * (every pixel of the object beside a background pixel) lies within 1.5 px
 * of a projected edge: the silhouette of these solids is made of their
 * sharp edges. */
static void check_solid(const char *name, int edges, int white) {
    char dir[512], path[600];
    snprintf(dir, sizeof dir, "%s/%s%s", tmp, name, white ? "_white" : "");
    ws_status st;
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    opt.views[WS_TRAIN] = 3;
    opt.views[WS_VAL] = 0;
    opt.views[WS_TEST] = 1;
    opt.size = 64;
    opt.white_background = white;
    int rc = ws_synth_write(name, dir, &opt, &st);
    CHECK(rc == WS_OK, "%s: %s", name, st.msg);
    if (rc) return;
    ws_curves gt;
    snprintf(path, sizeof path, "%s/gt_curves.json", dir);
    rc = ws_curves_load(path, &gt, &st);
    CHECK(rc == WS_OK && gt.n == edges, "%s: %d edges in gt_curves.json (%s)", name, gt.n, st.msg);
    if (rc) return;
    ws_pointcloud pc;
    snprintf(path, sizeof path, "%s/gt_points.ply", dir);
    rc = ws_pointcloud_load_ply(path, &pc, &st);
    CHECK(rc == WS_OK && pc.n == 20000, "%s: gt_points.ply: %s", name, st.msg);
    if (!rc) ws_pointcloud_free(&pc);
    ws_scene sc;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = opt.size;
    rc = ws_scene_load(&sc, dir, &so, &st);
    CHECK(rc == WS_OK, "%s load: %s", name, st.msg);
    if (rc) {
        ws_curves_free(&gt);
        return;
    }
    const float bg = white ? 1.0f : 0.0f;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < sc.split[s].n; k++) {
            const ws_view *v = &sc.split[s].views[k];
            const int W = v->photo.width, H = v->photo.height, S = 400;
            const float *im = v->photo.data;
            double *uv = malloc(sizeof *uv * 2 * gt.n * S);
            for (int ci = 0; ci < gt.n; ci++)
                for (int t = 0; t < S; t++) {
                    double p[3], c[3];
                    ws_curve_point(&gt, ci, t / (S - 1.0), p);
                    ws_camera_to_cam(&v->cam, p, c);
                    uv[2 * (ci * S + t)] = W / 2.0 + v->cam.focal * c[0] / -c[2];
                    uv[2 * (ci * S + t) + 1] = H / 2.0 - v->cam.focal * c[1] / -c[2];
                }
            int object = 0, outline = 0, far = 0;
            for (int i = 1; i + 1 < H; i++)
                for (int j = 1; j + 1 < W; j++) {
                    int at = i * W + j;
                    if (im[at] == bg && im[W * H + at] == bg && im[2 * W * H + at] == bg) continue;
                    object++;
                    int beside = 0;
                    for (int d = 0; d < 4; d++) {
                        int n = at + (d == 0 ? 1 : d == 1 ? -1 : d == 2 ? W : -W);
                        beside |= im[n] == bg && im[W * H + n] == bg && im[2 * W * H + n] == bg;
                    }
                    if (!beside) continue;
                    outline++;
                    double best = INFINITY;
                    for (int q = 0; q < gt.n * S; q++)
                        best = fmin(best, hypot(uv[2 * q] - j, uv[2 * q + 1] - i));
                    far += best > 1.5;
                }
            CHECK(object > W * H / 20 && object < W * H / 2, "%s %s: %d object pixels", name,
                  v->name, object);
            CHECK(im[0] == bg && im[W * H - 1] == bg, "%s %s: background %g", name, v->name, im[0]);
            CHECK(outline > 40 && far == 0, "%s %s: %d of %d outline pixels off the edges", name,
                  v->name, far, outline);
            free(uv);
        }
    ws_scene_free(&sc);
    ws_curves_free(&gt);
}

/* The bounding box of dense samples of the curves. */
static void curves_box(const ws_curves *c, double lo[3], double hi[3]) {
    for (int x = 0; x < 3; x++) {
        lo[x] = INFINITY;
        hi[x] = -INFINITY;
    }
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k <= 64; k++) {
            double p[3];
            ws_curve_point(c, ci, k / 64.0, p);
            for (int x = 0; x < 3; x++) {
                lo[x] = fmin(lo[x], p[x]);
                hi[x] = fmax(hi[x], p[x]);
            }
        }
}

/* The wire shapes are what their names promise: the spring a coil of 5
 * turns, radius 0.3, 1 unit tall, about the vertical through its centre;
 * the flat wire object has every control point in one plane, a plane
 * tilted (neither horizontal nor vertical) so that some views see it
 * edge-on, and it is a clip about 1.75 units across. */
static void test_wire_shapes(void) {
    ws_status st;
    ws_synth_object obj;
    int rc = ws_synth_object_make(&obj, "spring", &st);
    CHECK(rc == WS_OK, "spring: %s", st.msg);
    if (!rc) {
        double lo[3], hi[3], turns = 0, prev = NAN;
        curves_box(&obj.curves, lo, hi);
        CHECK(fabs(hi[2] - lo[2] - 1.0) < 1e-9, "spring: %.12g tall", hi[2] - lo[2]);
        for (int x = 0; x < 2; x++)
            CHECK(fabs(hi[x] - lo[x] - 0.6) < 0.01, "spring: %.4g wide along axis %d", hi[x] - lo[x], x);
        for (int ci = 0; ci < obj.curves.n; ci++)
            for (int k = 0; k < 64; k++) { /* windings: the angle about the axis, unwrapped */
                double p[3];
                ws_curve_point(&obj.curves, ci, k / 64.0, p);
                double a = atan2(p[1] - obj.center[1], p[0] - obj.center[0]);
                if (!isnan(prev)) turns += remainder(a - prev, 2 * M_PI) / (2 * M_PI);
                prev = a;
            }
        CHECK(fabs(fabs(turns) - 5) < 0.05, "spring: %.3g turns", turns);
        ws_synth_object_free(&obj);
    }
    rc = ws_synth_object_make(&obj, "flat", &st);
    CHECK(rc == WS_OK, "flat: %s", st.msg);
    if (!rc) {
        const double *P = obj.curves.P; /* the plane of the first leg's ends and the second's start */
        double u[3], v[3], n[3], worst = 0, lo[3], hi[3];
        for (int x = 0; x < 3; x++) {
            u[x] = P[9 + x] - P[x];
            v[x] = P[3 * WS_CURVE_FLOATS + x] - P[x];
        }
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        double nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int j = 0; j < 4 * obj.curves.n; j++) {
            double d = 0;
            for (int x = 0; x < 3; x++) d += (P[3 * j + x] - P[x]) * n[x] / nl;
            worst = fmax(worst, fabs(d));
        }
        CHECK(worst < 1e-12, "flat: a control point %g off its plane", worst);
        double tilt = acos(fabs(n[2]) / nl) * 180 / M_PI;
        CHECK(tilt > 20 && tilt < 70, "flat: its plane tilted %.3g degrees", tilt);
        curves_box(&obj.curves, lo, hi);
        double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
        CHECK(diag > 1.6 && diag < 1.9, "flat: diagonal %.3g", diag);
        ws_synth_object_free(&obj);
    }
}

/* The worst difference, over the background pixels (mask 0) of train
 * view 1 of the masked room scene in dir (96 x 72 frames, principal point
 * (58, 30)), between its photo and the room with its floor at floor_z as
 * ws_room_render sees it; *object and *background count the pixels (mask
 * > 1/2, mask 0); INFINITY when something could not be read. */
static double room_difference(const char *dir, double floor_z, long *object, long *background) {
    ws_status st;
    ws_scene sc;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 72;
    *object = *background = 0;
    if (ws_scene_load(&sc, dir, &so, &st)) return INFINITY;
    const ws_view *v = &sc.split[WS_TRAIN].views[1];
    ws_camera cam;
    ws_image photo = {0}, mask = {0}, room = {0};
    char path[700];
    snprintf(path, sizeof path, "%s/masks/train/r_1.png", dir);
    int rc = ws_camera_init_pinhole(&cam, v->cam.c2w, 0.5 * 72 / tan(atan(18.0 / 50.0)), 58, 30, 96, 72, "cam", &st) ||
             ws_image_read(v->image_path, 0, 0, (const float[3]){0, 0, 0}, &photo, &st) ||
             ws_image_read(path, 0, 0, (const float[3]){0, 0, 0}, &mask, &st) ||
             ws_room_render(&cam, sc.center, floor_z, 3, &room, &st);
    double worst = rc ? INFINITY : 0;
    for (size_t p = 0; !rc && p < (size_t)96 * 72; p++) {
        if (mask.data[p] > 0.5) {
            ++*object;
            continue;
        }
        if (mask.data[p] > 0) continue; /* partly covered */
        ++*background;
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(photo.data[c * 96 * 72 + p] - room.data[c * 96 * 72 + p]));
    }
    ws_image_free(&photo);
    ws_image_free(&mask);
    ws_image_free(&room);
    ws_scene_free(&sc);
    return worst;
}

/* The capture test bed's options (nerfstudio, 96 x 72, the principal point
 * (10, -6) px off the centre, the box room, masks): the file lists that
 * principal point and a mask_path per frame; the photo is the same with
 * masks or without (to a grey level: the masks' photo is composited from
 * two renders); where a mask says background (no ray of the
 * pixel hits the object) the photo is the room as ws_room_render sees it,
 * to a grey level; with --background floor the same, with the room's floor
 * at the cube's lowest corner (and not the room around a stand); a floor
 * point has one colour from any camera (the room is one 3D room in every
 * view) and the floor has a pattern; bad options get their one-line
 * messages. */
static void test_room(void) {
    ws_status st;
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    opt.views[WS_TRAIN] = 3;
    opt.views[WS_VAL] = opt.views[WS_TEST] = 1;
    opt.nerfstudio = opt.room = opt.masks = 1;
    opt.width = 96;
    opt.height = 72;
    opt.principal[0] = 10;
    opt.principal[1] = -6;
    char a[512], b[512], pa[700], pb[700];
    snprintf(a, sizeof a, "%s/room_masks", tmp);
    snprintf(b, sizeof b, "%s/room", tmp);
    int rc = ws_synth_write("cube", a, &opt, &st);
    opt.masks = 0;
    rc = rc || ws_synth_write("cube", b, &opt, &st);
    CHECK(rc == 0, "room scenes: %s", st.msg);
    if (rc) return;
    snprintf(pa, sizeof pa, "%s/rgb/train/r_1.png", a);
    snprintf(pb, sizeof pb, "%s/rgb/train/r_1.png", b);
    ws_image with = {0}, without = {0};
    rc = ws_image_read(pa, 0, 0, (const float[3]){0, 0, 0}, &with, &st) ||
         ws_image_read(pb, 0, 0, (const float[3]){0, 0, 0}, &without, &st);
    double moved = 0;
    for (size_t p = 0; !rc && p < (size_t)3 * 96 * 72; p++) moved = fmax(moved, fabs(with.data[p] - without.data[p]));
    CHECK(!rc && moved <= 1.0 / 255 + 1e-6, "the photo with masks and without: %g apart (%s)", moved, st.msg);
    ws_image_free(&with);
    ws_image_free(&without);
    size_t n = 0;
    snprintf(pa, sizeof pa, "%s/transforms.json", a);
    char *json = slurp(pa, &n);
    CHECK(json && strstr(json, "\"cx\":\t58") && strstr(json, "\"cy\":\t30") &&
              strstr(json, "\"mask_path\":\t\"masks/test/r_0.png\""),
          "principal point and mask_path in %s", pa);
    free(json);
    ws_scene sc;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 72;
    if (ws_scene_load(&sc, a, &so, &st)) {
        CHECK(0, "room scene: %s", st.msg);
        return;
    }
    long object, background;
    double worst = room_difference(a, sc.center[2] - WS_ROOM_FLOOR, &object, &background);
    CHECK(object > 100 && background > 1000 && worst <= 0.5 / 255 + 1e-6,
          "room photo: %ld object and %ld background pixels, worst difference from the room %g", object,
          background, worst);
    /* --background floor: the same room, its floor under the cube's lowest corner */
    char c[512];
    snprintf(c, sizeof c, "%s/floor_masks", tmp);
    opt.on_floor = opt.masks = 1;
    rc = ws_synth_write("cube", c, &opt, &st);
    opt.on_floor = opt.masks = 0;
    CHECK(rc == 0, "floor scene: %s", st.msg);
    ws_curves gt = {0};
    double lo[3] = {0, 0, 0}, hi[3];
    snprintf(pa, sizeof pa, "%s/gt_curves.json", c);
    if (!rc && !ws_curves_load(pa, &gt, &st)) ws_curves_bbox(&gt, lo, hi);
    ws_curves_free(&gt);
    double on_floor = rc ? INFINITY : room_difference(c, lo[2], &object, &background);
    double on_stand = rc ? 0 : room_difference(c, sc.center[2] - WS_ROOM_FLOOR, &object, &background);
    CHECK(on_floor <= 0.5 / 255 + 1e-6 && on_stand > 0.1 && lo[2] < sc.center[2] - 0.3,
          "floor photo: worst difference %g from the room with its floor at the cube's lowest point %g, %g from "
          "the room around a stand", on_floor, lo[2], on_stand);
    const double floor_point[3] = {sc.center[0] - 2.3, sc.center[1] + 1.7, sc.center[2] - WS_ROOM_FLOOR};
    const double from[2][3] = {{sc.center[0] + 1, sc.center[1], sc.center[2] + 0.5},
                               {sc.center[0] - 1, sc.center[1] + 2, sc.center[2] + 3}};
    float rgb[2][3], next[3];
    for (int k = 0; k < 2; k++) {
        double dir[3];
        for (int i = 0; i < 3; i++) dir[i] = floor_point[i] - from[k][i];
        ws_room_colour(sc.center, floor_point[2], from[k], dir, rgb[k]);
    }
    const double dir_next[3] = {floor_point[0] + 1 - from[0][0], floor_point[1] - from[0][1],
                                floor_point[2] - from[0][2]};
    ws_room_colour(sc.center, floor_point[2], from[0], dir_next, next);
    CHECK(!memcmp(rgb[0], rgb[1], sizeof rgb[0]) && memcmp(rgb[0], next, sizeof next),
          "a floor point: %g %g %g from one camera, %g %g %g from another; the next tile %g %g %g", rgb[0][0],
          rgb[0][1], rgb[0][2], rgb[1][0], rgb[1][1], rgb[1][2], next[0], next[1], next[2]);
    ws_scene_free(&sc);
    opt.principal[0] = 48;
    rc = ws_synth_write("cube", b, &opt, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, "--principal 48,-6: not inside the 96 x 72 image (offsets from its centre)"),
          "principal point out of the image: %s", st.msg);
    opt.principal[0] = 10;
    opt.nerfstudio = 0;
    opt.width = opt.height = 0;
    rc = ws_synth_write("cube", b, &opt, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, "--principal 10,-6: a NeRF-synthetic scene has its principal point at "
                                             "the centre (--layout nerfstudio or colmap takes others)"),
          "principal point in a NeRF-synthetic scene: %s", st.msg);
    opt.principal[0] = opt.principal[1] = 0;
    rc = ws_synth_write("torus", b, &opt, &st);
    CHECK(rc == WS_EUSAGE &&
              !strcmp(st.msg, "torus: --background room or floor and --masks are for the wire objects and solids"),
          "a smooth object in the room: %s", st.msg);
}

int main(void) {
    tmp = test_tmpdir("synth");
    const int trefoil_views[3] = {5, 2, 2}, chair_views[3] = {4, 0, 1}, wire_views[3] = {4, 1, 1};
    check_scene("trefoil", "trefoil", trefoil_views, 64, 12);
    check_scene("chair", "chair", chair_views, 96, 15);
    check_scene("spring", "spring", wire_views, 96, 20);
    check_scene("flat", "flat", wire_views, 96, 10);
    test_wire_shapes();
    check_solid("cube", 12, 0);
    check_solid("dodecahedron", 30, 1);
    check_solid("nut", 26, 0);
    check_solid("bracket", 18, 1);
    test_deterministic();
    test_errors();
    test_room();
    return check_summary();
}
