/* test_regressions.c: the fuzzers' findings stay fixed, and their seeds stay
 * valid.
 *
 * Every file under tests/fuzz/regressions/TARGET/ is an input that once
 * crashed a loader or got an answer that was not one clean line; each is fed
 * to its loader as the fuzz target feeds it (tests/fuzz/fuzz_TARGET.c) and
 * must be refused with WS_EINPUT and exactly the message of the table below,
 * which starts with the file's path. Weight files and checkpoints are stored
 * with the checksum the fuzz target gave them (fuzz_input.h), so they reach
 * the same code. Every seed under tests/fuzz/corpus/TARGET/ must load. Run
 * under `make test SANITIZE=1`, a memory error here is a failure too. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_util.h"
#include "fit/checkpoint.h"
#include "nn/clip.h"
#include "render/curves.h"
#include "io/image.h"
#include "base/outfile.h"
#include "io/pointcloud.h"
#include "io/scene.h"

/* A scene directory with train/r_0.png .. train/r_2.png, as fuzz_scene.c
 * makes it; each scene input is copied in as its transforms_train.json. */
static const char *scene_dir;

static int load_png(const char *path, ws_status *st) {
    static const float background[3] = {0.25f, 0.5f, 0.75f};
    ws_image img;
    int rc = ws_image_read(path, 12, 10, background, &img, st);
    if (!rc) ws_image_free(&img);
    return rc;
}

static int load_curves(const char *path, ws_status *st) {
    ws_curves c;
    int rc = ws_curves_load(path, &c, st);
    if (!rc) ws_curves_free(&c);
    return rc;
}

static int load_weights(const char *path, ws_status *st) {
    clip_model *m;
    int rc = clip_model_load(&m, path, st);
    if (!rc) clip_model_free(m);
    return rc;
}

static int load_ply(const char *path, ws_status *st) {
    ws_pointcloud pc;
    int rc = ws_pointcloud_load_ply(path, &pc, st);
    if (!rc) ws_pointcloud_free(&pc);
    return rc;
}

static int load_checkpoint(const char *path, ws_status *st) {
    ws_fit_state s;
    int argc;
    char **argv;
    int rc = ws_checkpoint_load(path, &s, &argc, &argv, st);
    if (!rc) {
        ws_fit_state_free(&s);
        ws_checkpoint_free_args(argc, argv);
    }
    return rc;
}

/* The path the scene loader names: the copy of the input. */
static char scene_json[300];

static int load_scene(const char *path, ws_status *st) {
    char cmd[1024];
    snprintf(scene_json, sizeof scene_json, "%s/transforms_train.json", scene_dir);
    snprintf(cmd, sizeof cmd, "cp '%s' '%s'", path, scene_json);
    if (system(cmd) != 0) return ws_fail(st, WS_EINTERNAL, "cannot copy %s", path);
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = opt.height = 8;
    ws_scene scene;
    int rc = ws_scene_load(&scene, scene_dir, &opt, st);
    if (!rc) ws_scene_free(&scene);
    return rc;
}

static const struct {
    const char *name;
    int (*load)(const char *path, ws_status *st);
    int names_copy; /* the message names the copy in scene_dir */
} targets[] = {
    {"scene", load_scene, 1},     {"png", load_png, 0},           {"weights", load_weights, 0},
    {"curves", load_curves, 0},   {"checkpoint", load_checkpoint, 0}, {"ply", load_ply, 0},
};

/* Each regression input and the message it gets (after "PATH"). */
static const struct {
    const char *target, *file, *message;
} regressions[] = {
    {"scene", "file_path_newline.json", ": frame 0: file_path contains a control character"},
    {"scene", "file_path_parent.json",
     ": frame 0: file_path 'train/../../r_0' leaves the scene directory ('..')"},
    {"scene", "camera_angle_tiny.json", ": camera_angle_x 1e-300 is not in [0.001, pi - 0.001]"},
    {"scene", "rotation_scaled.json",
     ": frame 0: transform_matrix's rotation is not orthonormal (R^T R differs from I by 1e+200)"},
    {"scene", "bottom_row.json", ": frame 0: transform_matrix's bottom row is not 0 0 0 1"},
    {"weights", "tensor_name_newline.bin", ": tensor table entry 0 has a malformed name"},
    {"weights", "tensors_200000.bin", ": 200000 tensors in the table, a 1-layer CLIP tower has 20"},
    {"weights", "tensor_beyond_layers.bin", ": 21 tensors in the table, a 1-layer CLIP tower has 20"},
    {"curves", "too_long_to_measure.json", ": curve 0 is too long to measure"},
    {"checkpoint", "thickness_negative.bin", ": corrupt checkpoint (curve thickness or overlap)"},
};
enum { NREGRESSIONS = sizeof regressions / sizeof regressions[0] };

static int by_name(const struct dirent **a, const struct dirent **b) {
    return strcmp((*a)->d_name, (*b)->d_name);
}

/* The regular files of dir, sorted (0 when dir does not exist). */
static int list_files(const char *dir, struct dirent ***names) {
    int n = scandir(dir, names, NULL, by_name);
    if (n < 0) {
        *names = NULL;
        return 0;
    }
    int kept = 0;
    for (int i = 0; i < n; i++) {
        if ((*names)[i]->d_name[0] != '.')
            (*names)[kept++] = (*names)[i];
        else
            free((*names)[i]);
    }
    return kept;
}

static void check_regressions(int t, int *seen) {
    char dir[300], path[600], want[1200];
    snprintf(dir, sizeof dir, "tests/fuzz/regressions/%s", targets[t].name);
    struct dirent **files;
    int n = list_files(dir, &files);
    for (int i = 0; i < n; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]->d_name);
        int k = 0;
        while (k < NREGRESSIONS && (strcmp(regressions[k].target, targets[t].name) ||
                                    strcmp(regressions[k].file, files[i]->d_name)))
            k++;
        CHECK(k < NREGRESSIONS, "%s: no expected message in test_regressions.c", path);
        ws_status st = {0};
        int rc = targets[t].load(path, &st);
        if (k == NREGRESSIONS) {
            free(files[i]);
            continue;
        }
        seen[k] = 1;
        snprintf(want, sizeof want, "%s%s", targets[t].names_copy ? scene_json : path,
                 regressions[k].message);
        CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "%s: code %d, message '%s', expected '%s'",
              path, rc, st.msg, want);
        free(files[i]);
    }
    free(files);
}

static void check_seeds(int t) {
    char dir[300], path[600];
    snprintf(dir, sizeof dir, "tests/fuzz/corpus/%s", targets[t].name);
    struct dirent **files;
    int n = list_files(dir, &files);
    CHECK(n > 0, "%s: no seeds", dir);
    for (int i = 0; i < n; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]->d_name);
        ws_status st = {0};
        CHECK(targets[t].load(path, &st) == WS_OK, "seed %s does not load: %s", path, st.msg);
        free(files[i]);
    }
    free(files);
}

static int make_scene_dir(void) {
    scene_dir = test_tmpdir("regressions");
    char path[400];
    snprintf(path, sizeof path, "%s/train", scene_dir);
    ws_status st = {0};
    ws_image img;
    if (ws_mkdir(path, &st) || ws_image_alloc(&img, 4, 3, 3, &st)) return 0;
    for (int i = 0; i < 4 * 3 * 3; i++) img.data[i] = (float)(i % 7) / 6.0f;
    int ok = 1;
    for (int k = 0; k < 3 && ok; k++) {
        snprintf(path, sizeof path, "%s/train/r_%d.png", scene_dir, k);
        ok = ws_png_write(path, &img, &st) == WS_OK;
    }
    ws_image_free(&img);
    return ok;
}

int main(void) {
    CHECK(make_scene_dir(), "cannot make the scene directory");
    int seen[NREGRESSIONS] = {0};
    for (size_t t = 0; t < sizeof targets / sizeof targets[0]; t++) {
        check_regressions((int)t, seen);
        check_seeds((int)t);
    }
    for (int k = 0; k < NREGRESSIONS; k++)
        CHECK(seen[k], "tests/fuzz/regressions/%s/%s is missing", regressions[k].target,
              regressions[k].file);
    return check_summary();
}
