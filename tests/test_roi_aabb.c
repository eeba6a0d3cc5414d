/* test_roi_aabb.c: the region of interest from a transforms file's
 * instant-ngp "aabb" (io/transforms.h, geometry/roi.h). On a small cube in
 * the box room (nerfstudio and NeRF-synthetic layouts, cameras only):
 *   - without an aabb the box comes from the nerfstudio file's sparse
 *     points (ply_file_path, which `scene` writes as ns-process-data
 *     does), and without those from where the cameras look;
 *   - with one, the region of interest is that box exactly, its line says
 *     "aabb", and --bbox still wins over it;
 *   - aabb_scale alone is no box (it is not read);
 *   - an aabb that is not two triples of finite numbers, or is empty along
 *     an axis, fails the load with its one-line message;
 *   - a region that cannot be found (a train view blind to where the
 *     cameras look, no points) does not fail the load every command makes
 *     (ws_roi_load_scene): it is kept for whoever needs the region. */
#define _XOPEN_SOURCE 700
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "geometry/roi.h"
#include "scene_load.h"
#include "synth/synth.h"
#include "test_util.h"

enum { SIZE = 32, TRAIN = 8 };

/* Loads the scene's cameras only (the box needs no pixels). */
static int load_cameras(ws_scene *scene, const char *dir, ws_status *st) {
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = SIZE;
    so.load_images = 0;
    return ws_scene_load(scene, dir, &so, st);
}

/* Rewrites `path` with `insert` put `keep` characters after the start of
 * the first `anchor` in it, in place of the `cut` characters there; 0 on
 * success. */
static int splice(const char *path, const char *anchor, size_t keep, size_t cut, const char *insert) {
    FILE *f = fopen(path, "rb");
    if (!f) return 1;
    static char text[1 << 20];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    char *at = strstr(text, anchor);
    if (!at || !(f = fopen(path, "wb"))) return 1;
    fwrite(text, 1, (size_t)(at + keep - text), f);
    fputs(insert, f);
    fputs(at + keep + cut, f);
    return fclose(f) != 0;
}

/* Rewrites `path` with `keys` ("\"aabb\": ..., ") right after its opening
 * brace; 0 on success. */
static int add_keys(const char *path, const char *keys) { return splice(path, "{", 1, 0, keys); }

/* Copies src to dst byte for byte; 0 on success. */
static int copy_file(const char *src, const char *dst) {
    FILE *a = fopen(src, "rb"), *b = a ? fopen(dst, "wb") : NULL;
    int c, rc = !b;
    while (b && (c = fgetc(a)) != EOF) fputc(c, b);
    if (a) fclose(a);
    if (b) rc |= fclose(b) != 0;
    return rc;
}

/* The scene at dir with its file `file` (original copy at `saved`) given
 * `keys`: the load fails with exactly `message`, or, when message is NULL,
 * loads and finds the aabb as the ROI `lo`..`hi`. */
static void with_keys(const char *dir, const char *file, const char *saved, const char *keys, const char *message,
                      const double lo[3], const double hi[3]) {
    char path[400];
    ws_status st;
    ws_scene scene = {0};
    snprintf(path, sizeof path, "%s/%s", dir, file);
    CHECK(copy_file(saved, path) == 0 && add_keys(path, keys) == 0, "%s: could not write %s", path, keys);
    int rc = load_cameras(&scene, dir, &st);
    if (message) {
        CHECK(rc == WS_EINPUT && !strcmp(st.msg, message), "%s:\n  got      %s\n  expected %s", keys, st.msg,
              message);
    } else {
        ws_roi roi;
        CHECK(rc == WS_OK && scene.has_aabb, "%s: %s (has_aabb %d)", keys, st.msg, scene.has_aabb);
        rc = rc || ws_roi_find(&scene, NULL, &roi, &st);
        CHECK(rc == WS_OK && roi.source == WS_ROI_AABB, "%s: %s (source %d)", keys, st.msg, roi.source);
        if (!rc) {
            printf("%s\n", roi.line);
            for (int a = 0; a < 3; a++)
                CHECK(roi.lo[a] == lo[a] && roi.hi[a] == hi[a], "%s: along %c [%g, %g], not [%g, %g]", keys,
                      "xyz"[a], roi.lo[a], roi.hi[a], lo[a], hi[a]);
            char expected[200];
            snprintf(expected, sizeof expected, "from the aabb of %s", file);
            CHECK(strstr(roi.line, expected) != NULL, "the line does not name the aabb: %s", roi.line);
            const double user[6] = {-0.5, -0.5, -0.5, 0.5, 0.5, 0.5};
            CHECK(ws_roi_find(&scene, user, &roi, &st) == WS_OK && roi.source == WS_ROI_USER && roi.hi[0] == 0.5,
                  "--bbox does not win over the aabb");
        }
    }
    ws_scene_free(&scene);
}

static void layout(const char *tmp, const char *name, int nerfstudio, const char *file) {
    char dir[300], path[400], saved[400], message[600];
    ws_status st;
    ws_synth_options syn;
    synth_options_at(&syn, SIZE, TRAIN, 0, 2);
    syn.room = 1;
    syn.nerfstudio = nerfstudio;
    snprintf(dir, sizeof dir, "%s/%s", tmp, name);
    snprintf(path, sizeof path, "%s/%s", dir, file);
    snprintf(saved, sizeof saved, "%s/%s.saved", tmp, name);
    int rc = ws_synth_write("cube", dir, &syn, &st);
    CHECK(rc == WS_OK, "%s: %s", name, st.msg);
    if (rc) return;
    CHECK(copy_file(path, saved) == 0, "%s: could not copy %s", name, path);

    /* no aabb: the sparse points of a nerfstudio file (ply_file_path),
     * else where the cameras look */
    const ws_roi_source without = nerfstudio ? WS_ROI_POINTS : WS_ROI_CAMERAS;
    ws_scene scene = {0};
    ws_roi roi;
    rc = load_cameras(&scene, dir, &st) || ws_roi_find(&scene, NULL, &roi, &st);
    CHECK(rc == WS_OK && !scene.has_aabb && roi.source == without, "%s without an aabb: %s (source %d)",
          name, st.msg, roi.source);
    ws_scene_free(&scene);
    if (nerfstudio) {
        const char *key = "\"ply_file_path\"";
        CHECK(copy_file(saved, path) == 0 && splice(path, key, 0, strlen(key), "\"ply_file_PATH\"") == 0,
              "could not write %s", path);
        rc = load_cameras(&scene, dir, &st) || ws_roi_find(&scene, NULL, &roi, &st);
        CHECK(rc == WS_OK && roi.source == WS_ROI_CAMERAS, "%s without its sparse points: %s (source %d)", name,
              st.msg, roi.source);
        ws_scene_free(&scene);
        /* no sparse points and a train view that does not see where the
         * cameras look: no region; the scene still loads as every command
         * loads it, unzoomed, and the failure waits for whoever needs the
         * region (a fit without masks); --bbox gives one */
        const char *frames = "\"frames\":\t[{";
        CHECK(copy_file(saved, path) == 0 && splice(path, key, 0, strlen(key), "\"ply_file_PATH\"") == 0 &&
                  splice(path, frames, strlen(frames), 0, "\"cx\": 400, ") == 0,
              "could not write %s", path);
        ws_scene_options so;
        ws_scene_options_default(&so);
        so.width = so.height = SIZE;
        so.load_images = 0;
        ws_status roi_st;
        char blind[600];
        snprintf(blind, sizeof blind, "%s: train view 0 does not see the point the cameras look at, so the cameras "
                 "give no region of interest (give one with --bbox)", path);
        rc = ws_roi_load_scene(&scene, dir, &so, NULL, &roi, &roi_st, &st);
        CHECK(rc == WS_OK && roi_st.code == WS_EINPUT && !strcmp(roi_st.msg, blind) && scene.zoomed == 0,
              "%s, a view blind to the centre: %s; the region's failure: %s", name, st.msg, roi_st.msg);
        ws_scene_free(&scene);
        const double user[6] = {-0.5, -0.5, -0.5, 0.5, 0.5, 0.5};
        rc = ws_roi_load_scene(&scene, dir, &so, user, &roi, &roi_st, &st);
        CHECK(rc == WS_OK && roi_st.code == WS_OK && roi.source == WS_ROI_USER,
              "%s, a view blind to the centre, with --bbox: %s (source %d)", name, st.msg, roi.source);
        ws_scene_free(&scene);
        /* a ply_file_path that names no file: the cameras' box, and its line says why */
        char ply[400], away[400], why[600];
        snprintf(ply, sizeof ply, "%s/sparse_pc.ply", dir);
        snprintf(away, sizeof away, "%s/sparse_pc.away", dir);
        snprintf(why, sizeof why, "every train view sees whole); the sparse points %s (ply_file_path) are not there",
                 ply);
        CHECK(copy_file(saved, path) == 0 && rename(ply, away) == 0, "could not move %s", ply);
        rc = load_cameras(&scene, dir, &st) || ws_roi_find(&scene, NULL, &roi, &st);
        CHECK(rc == WS_OK && roi.source == WS_ROI_CAMERAS && strstr(roi.line, why),
              "%s with its sparse points gone: %s (source %d): %s", name, st.msg, roi.source, roi.line);
        ws_scene_free(&scene);
        CHECK(rename(away, ply) == 0, "could not move %s back", ply);
    }

    const double lo[3] = {-0.75, -0.5, -0.25}, hi[3] = {0.75, 0.625, 1.5};
    with_keys(dir, file, saved, "\"aabb\": [[-0.75, -0.5, -0.25], [0.75, 0.625, 1.5]], ", NULL, lo, hi);
    with_keys(dir, file, saved, "\"aabb_scale\": 16, \"aabb\": [[-0.75, -0.5, -0.25], [0.75, 0.625, 1.5]], ", NULL,
              lo, hi);

    /* aabb_scale alone: no box */
    CHECK(copy_file(saved, path) == 0 && add_keys(path, "\"aabb_scale\": 16, ") == 0, "could not write %s", path);
    rc = load_cameras(&scene, dir, &st) || ws_roi_find(&scene, NULL, &roi, &st);
    CHECK(rc == WS_OK && !scene.has_aabb && roi.source == without, "%s with aabb_scale: %s (source %d)",
          name, st.msg, roi.source);
    ws_scene_free(&scene);

    snprintf(message, sizeof message, "%s: aabb is not two triples of finite numbers [[x0,y0,z0],[x1,y1,z1]]", path);
    static const char *const not_boxes[] = {
        "\"aabb\": [[0, 0, 0], [1, 1]], ",         "\"aabb\": [[0, 0, 0], [1, 1, 1], [2, 2, 2]], ",
        "\"aabb\": [0, 0, 0, 1, 1, 1], ",           "\"aabb\": [[0, 0, 0], [1, \"1\", 1]], ",
        "\"aabb\": [[0, 0, 0], [1, 1e999, 1]], ",   "\"aabb\": 16, ",
    };
    for (size_t k = 0; k < sizeof not_boxes / sizeof *not_boxes; k++)
        with_keys(dir, file, saved, not_boxes[k], message, NULL, NULL);
    snprintf(message, sizeof message, "%s: aabb is empty along y (1 >= 0.5)", path);
    with_keys(dir, file, saved, "\"aabb\": [[0, 1, 0], [1, 0.5, 1]], ", message, NULL, NULL);
    snprintf(message, sizeof message, "%s: aabb is empty along z (2 >= 2)", path);
    with_keys(dir, file, saved, "\"aabb\": [[0, 0, 2], [1, 1, 2]], ", message, NULL, NULL);
}

int main(void) {
    const char *tmp = test_tmpdir("roi_aabb");
    layout(tmp, "nerfstudio", 1, "transforms.json");
    layout(tmp, "synthetic", 0, "transforms_train.json");
    return check_summary();
}
