/* test_transforms.c: io/transforms.h, the one reader and writer of the
 * transforms JSON: what it writes reads back the same (frames, intrinsics,
 * lens, splits), a rewrite makes exactly its edits, and bad files get
 * their one-line messages. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "io/transforms.h"
#include "tests/check.h"
#include "tests/test_util.h"

static const char *tmp;

static void frame_matrix(double c2w[4][4], double shift) {
    memset(c2w, 0, sizeof(double[4][4]));
    for (int i = 0; i < 4; i++) c2w[i][i] = 1;
    c2w[0][3] = shift, c2w[1][3] = 2, c2w[2][3] = 3.5;
}

static void write_text(const char *path, const char *text) {
    FILE *f = fopen(path, "wb");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* A nerfstudio file of three frames (train, train, test) with an OPENCV
 * lens with k3, read back: the same intrinsics, lens, paths, matrices and
 * splits; then rewritten: frame 1 dropped, frame 0 flipped, frame 2 on
 * frame 0's camera, focals doubled. */
static void test_nerfstudio_round_trip(void) {
    char path[400], fixed[400];
    snprintf(path, sizeof path, "%s/transforms.json", tmp);
    snprintf(fixed, sizeof fixed, "%s/fixed.json", tmp);
    ws_transforms_frame frames[3] = {{"images/a.png", "masks/a.png", NULL, {{0}}, WS_TRAIN},
                                     {"images/b.png", NULL, NULL, {{0}}, WS_TRAIN},
                                     {"images/c.png", NULL, "edges/c.png", {{0}}, WS_TEST}};
    for (int k = 0; k < 3; k++) frame_matrix(frames[k].c2w, k);
    ws_transforms_camera cam = {300, 310, 150.5, 99.25, 288, 224, {.fisheye = 0}};
    cam.lens.k[0] = 0.05, cam.lens.k[1] = -0.02, cam.lens.k[2] = 0.001, cam.lens.p[0] = 0.001, cam.lens.p[1] = -0.002;
    ws_status st;
    int rc = ws_transforms_write_nerfstudio(path, &cam, "sparse_pc.ply", frames, 3, &st);
    CHECK(rc == 0, "write: %s", st.msg);
    ws_transforms *t = NULL;
    rc = ws_transforms_open(&t, path, WS_TRANSFORMS_NERFSTUDIO, &st);
    CHECK(rc == 0 && ws_transforms_count(t) == 3, "open: %s", st.msg);
    if (rc) return;
    const char *ply;
    CHECK(ws_transforms_ply_file(t, &ply, &st) == 0 && ply && !strcmp(ply, "sparse_pc.ply"), "ply_file_path: %s",
          ply ? ply : "none");
    int split_of[3];
    CHECK(ws_transforms_splits(t, split_of, &st) == 0 && split_of[0] == WS_TRAIN && split_of[1] == WS_TRAIN &&
              split_of[2] == WS_TEST,
          "splits %d %d %d", split_of[0], split_of[1], split_of[2]);
    for (int k = 0; k < 3; k++) {
        ws_transforms_frame f;
        ws_transforms_camera c;
        rc = ws_transforms_frame_read(t, k, "frame", &f, &st) || ws_transforms_camera_read(t, k, "frame", &c, &st);
        CHECK(rc == 0, "frame %d: %s", k, st.msg);
        if (rc) continue;
        CHECK(!strcmp(f.file_path, frames[k].file_path) && !memcmp(f.c2w, frames[k].c2w, sizeof f.c2w),
              "frame %d: file_path %s", k, f.file_path);
        CHECK((f.mask_path != NULL) == (k == 0) && (f.edge_path != NULL) == (k == 2), "frame %d: optional paths", k);
        CHECK(c.fx == 300 && c.fy == 310 && c.cx == 150.5 && c.cy == 99.25 && c.w == 288 && c.h == 224,
              "frame %d: intrinsics %g %g %g %g %d %d", k, c.fx, c.fy, c.cx, c.cy, c.w, c.h);
        CHECK(!c.lens.fisheye && c.lens.k[0] == 0.05 && c.lens.k[1] == -0.02 && c.lens.k[2] == 0.001 &&
                  c.lens.k[3] == 0 && c.lens.p[0] == 0.001 && c.lens.p[1] == -0.002,
              "frame %d: lens", k);
    }
    const int camera[3] = {0, 1, 0};
    const char flip[3] = {1, 0, 0}, drop[3] = {0, 1, 0};
    const ws_transforms_edit edit = {camera, flip, drop, 2, split_of};
    rc = ws_transforms_rewrite(t, &edit, fixed, &st);
    CHECK(rc == 0, "rewrite: %s", st.msg);
    ws_transforms_close(t);
    rc = ws_transforms_open(&t, fixed, WS_TRANSFORMS_NERFSTUDIO, &st);
    CHECK(rc == 0 && ws_transforms_count(t) == 2, "open the rewrite: %s", st.msg);
    if (rc) return;
    ws_transforms_frame f0, f1;
    ws_transforms_camera c;
    rc = ws_transforms_frame_read(t, 0, "f0", &f0, &st) || ws_transforms_frame_read(t, 1, "f1", &f1, &st) ||
         ws_transforms_camera_read(t, 0, "f0", &c, &st) || ws_transforms_splits(t, split_of, &st);
    CHECK(rc == 0, "read the rewrite: %s", st.msg);
    if (!rc) {
        CHECK(c.fx == 600 && c.fy == 620 && c.cx == 150.5, "rewrite: fl_x %g fl_y %g cx %g", c.fx, c.fy, c.cx);
        CHECK(f0.c2w[1][1] == -1 && f0.c2w[2][2] == -1 && f0.c2w[0][0] == 1 && f0.c2w[0][3] == 0, "rewrite: flip");
        CHECK(!strcmp(f1.file_path, "images/c.png") && f1.c2w[0][3] == 0, "rewrite: frame 2 on frame 0's camera");
        CHECK(split_of[0] == WS_TRAIN && split_of[1] == WS_TEST, "rewrite: lists %d %d", split_of[0], split_of[1]);
    }
    ws_transforms_close(t);
}

/* A NeRF-synthetic split file read back; a fisheye lens writes k1..k4. */
static void test_split_file(void) {
    char path[400];
    snprintf(path, sizeof path, "%s/transforms_train.json", tmp);
    ws_transforms_frame frame = {"train/r_0", NULL, NULL, {{0}}, WS_TRAIN};
    frame_matrix(frame.c2w, 1);
    const double center[3] = {0.3, -0.2, 0.5};
    ws_status st;
    ws_transforms *t = NULL;
    int rc = ws_transforms_write_split(path, 0.6911, center, &frame, 1, &st) ||
             ws_transforms_open(&t, path, WS_TRANSFORMS_SPLIT, &st);
    CHECK(rc == 0 && ws_transforms_angle(t) == 0.6911 && !strcmp(ws_transforms_file_path(t, 0), "train/r_0"),
          "split file: %s", rc ? st.msg : "");
    ws_transforms_close(t);
    snprintf(path, sizeof path, "%s/fisheye.json", tmp);
    ws_transforms_camera cam = {200, 200, 100, 100, 200, 200, {.fisheye = 0}};
    cam.lens.fisheye = 1, cam.lens.k[0] = 0.01, cam.lens.k[3] = 0.001;
    ws_transforms_camera c;
    const char *ply = "";
    rc = ws_transforms_write_nerfstudio(path, &cam, NULL, &frame, 1, &st) ||
         ws_transforms_open(&t, path, WS_TRANSFORMS_NERFSTUDIO, &st) || ws_transforms_camera_read(t, 0, "f", &c, &st) ||
         ws_transforms_ply_file(t, &ply, &st);
    CHECK(rc == 0 && c.lens.fisheye && c.lens.k[0] == 0.01 && c.lens.k[3] == 0.001, "fisheye: %s", rc ? st.msg : "");
    CHECK(rc == 0 && ply == NULL, "a file without ply_file_path names one: %s", ply ? ply : "");
    ws_transforms_close(t);
}

/* Bad files: each its one line. */
static void test_bad_files(void) {
    const struct {
        const char *text, *message;
        int kind;
    } bad[] = {
        {"{\"frames\": []}", "bad.json: no frames", WS_TRANSFORMS_NERFSTUDIO},
        {"{\"frames\": [", "bad.json: JSON syntax error near line 1", WS_TRANSFORMS_NERFSTUDIO},
        {"[1]", "bad.json: not a JSON object", WS_TRANSFORMS_NERFSTUDIO},
        {"{\"frames\": [{}]}", "bad.json: missing camera_angle_x", WS_TRANSFORMS_SPLIT},
    };
    char path[400];
    snprintf(path, sizeof path, "%s/bad.json", tmp);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        write_text(path, bad[k].text);
        ws_status st;
        ws_transforms *t = NULL;
        int rc = ws_transforms_open(&t, path, bad[k].kind, &st);
        CHECK(rc == WS_EINPUT && strstr(st.msg, bad[k].message) && !t, "%s: %s", bad[k].text, st.msg);
    }
    write_text(path, "{\"frames\": [{\"file_path\": \"a.png\", \"mask_path\": 3, \"transform_matrix\": "
                     "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]}");
    ws_status st;
    ws_transforms *t = NULL;
    ws_transforms_frame f;
    int rc = ws_transforms_open(&t, path, WS_TRANSFORMS_NERFSTUDIO, &st) ||
             ws_transforms_frame_read(t, 0, "bad.json: frame 0", &f, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, "bad.json: frame 0: mask_path is not a string"), "mask_path: %s", st.msg);
    ws_transforms_close(t);
}

int main(void) {
    tmp = test_tmpdir("transforms");
    test_nerfstudio_round_trip();
    test_split_file();
    test_bad_files();
    return check_summary();
}
