/* test_masks.c: masks from a masks folder (scene.h): SCENE/masks of a
 * COLMAP or nerfstudio scene found by itself, `--masks DIR`, a frame's
 * mask_path winning, COLMAP's image.jpg.png names; what `scene --masks`
 * writes is what the loader finds, in the COLMAP layout as in nerfstudio's
 * (the same masks from both); the line that says where masks came from;
 * and each bad input's one-line message. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "io/scene.h"
#include "synth/synth.h"
#include "tests/check.h"
#include "tests/test_util.h"

static const char *tmp;

/* A small cube over the box room, with masks, in `layout` (1: nerfstudio,
 * 2: COLMAP). */
static int make_scene(const char *dir, int layout) {
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    opt.views[WS_TRAIN] = 8, opt.views[WS_VAL] = 1, opt.views[WS_TEST] = 1;
    opt.width = 48, opt.height = 40;
    opt.room = 1, opt.masks = 1;
    opt.nerfstudio = layout == 1;
    opt.colmap = layout == 2;
    ws_status st;
    int rc = ws_synth_write("cube", dir, &opt, &st);
    CHECK(rc == 0, "scene %s: %s", dir, st.msg);
    return rc;
}

static int load(ws_scene *sc, const char *dir, const char *masks_dir, ws_status *st) {
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = opt.height = 32;
    opt.masks_dir = masks_dir;
    return ws_scene_load(sc, dir, &opt, st);
}

static int every_view_masked(const ws_scene *sc) {
    int all = 1;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < sc->split[s].n; k++) all &= sc->split[s].views[k].mask.data != NULL;
    return all;
}

/* Do two loads of one 32 x 32 scene hold the same masks? */
static int same_masks(const ws_scene *a, const ws_scene *b) {
    int same = 1;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < a->split[s].n; k++)
            same &= !memcmp(a->split[s].views[k].mask.data, b->split[s].views[k].mask.data, sizeof(float) * 32 * 32);
    return same;
}

int main(void) {
    tmp = test_tmpdir("masks");
    char out[8192], colmap[400], ns[400], want[2048], line[1024];
    snprintf(colmap, sizeof colmap, "%s/colmap", tmp);
    snprintf(ns, sizeof ns, "%s/ns", tmp);
    if (make_scene(colmap, 2) || make_scene(ns, 1)) return check_summary();
    ws_scene c, n;
    ws_status st;
    /* COLMAP: SCENE/masks found by itself, one mask per view, the same
     * masks as the nerfstudio scene's mask_path give (the same cameras) */
    int rc = load(&c, colmap, NULL, &st);
    CHECK(rc == 0, "colmap with masks: %s", st.msg);
    if (rc) return check_summary();
    CHECK(every_view_masked(&c) && c.masks_from_dir == 10 && c.masks_from_paths == 0, "colmap: %d masks from the folder",
          c.masks_from_dir);
    ws_scene_mask_line(&c, line, sizeof line);
    snprintf(want, sizeof want, "%s: masks for 10 of 10 views from %s/masks", colmap, colmap);
    CHECK(!strcmp(line, want), "colmap mask line: %s", line);
    rc = load(&n, ns, NULL, &st);
    CHECK(rc == 0 && every_view_masked(&n) && n.masks_from_paths == 10 && n.masks_from_dir == 0,
          "nerfstudio with mask_path: %s", rc ? st.msg : "");
    if (!rc) {
        CHECK(same_masks(&n, &c), "the COLMAP layout's masks are the nerfstudio layout's");
        ws_scene_mask_line(&n, line, sizeof line);
        snprintf(want, sizeof want, "%s: masks for 10 of 10 views from the frames' mask_path", ns);
        CHECK(!strcmp(line, want), "nerfstudio mask line: %s", line);
        ws_scene_free(&n);
    }
    /* a mask_path wins over --masks DIR */
    rc = load(&n, ns, colmap, &st);
    CHECK(rc == 0 && n.masks_from_paths == 10 && n.masks_from_dir == 0, "mask_path wins: %s", rc ? st.msg : "");
    if (!rc) ws_scene_free(&n);
    /* --masks DIR: the COLMAP scene's masks moved elsewhere, one renamed
     * as COLMAP names masks (image.png.png) */
    run_cmd(out, sizeof out, "mv %s/masks %s/elsewhere && mv %s/elsewhere/train/r_00002.png %s/elsewhere/train/r_00002.png.png",
            colmap, tmp, tmp, tmp);
    char elsewhere[400];
    snprintf(elsewhere, sizeof elsewhere, "%s/elsewhere", tmp);
    ws_scene e;
    rc = load(&e, colmap, elsewhere, &st);
    CHECK(rc == 0 && every_view_masked(&e) && e.masks_from_dir == 10, "--masks DIR: %s", rc ? st.msg : "");
    if (!rc) {
        CHECK(same_masks(&e, &c), "--masks DIR: the same masks");
        ws_scene_free(&e);
    }
    ws_scene_free(&c);
    /* without masks: none, and no line */
    rc = load(&c, colmap, NULL, &st);
    CHECK(rc == 0 && c.split[WS_TRAIN].views[0].mask.data == NULL, "colmap without masks: %s", rc ? st.msg : "");
    if (!rc) {
        ws_scene_mask_line(&c, line, sizeof line);
        CHECK(line[0] == '\0', "no masks, no line: %s", line);
        ws_scene_free(&c);
    }
    /* bad input: a folder that does not exist */
    snprintf(want, sizeof want, "--masks %s/nowhere: no such folder", tmp);
    snprintf(line, sizeof line, "%s/nowhere", tmp);
    rc = load(&c, colmap, line, &st);
    CHECK(rc == WS_EUSAGE && !strcmp(st.msg, want), "missing --masks folder: %s", st.msg);
    /* an image with no mask where the folder has the others' */
    run_cmd(out, sizeof out, "mv %s/train/r_00005.png %s/r_00005.png", elsewhere, tmp);
    snprintf(want, sizeof want,
             "%s: no mask for train/r_00005.png (tried %s/train/r_00005.png and %s/train/r_00005.png.png), though "
             "the folder has the masks of 9 other views",
             elsewhere, elsewhere, elsewhere);
    rc = load(&c, colmap, elsewhere, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "a view without its mask: %s", st.msg);
    /* a mask of another size than its image */
    run_cmd(out, sizeof out, "cp %s/masks/train/r_1.png %s/train/r_00005.png && cp %s/r_00005.png %s/small.png", ns,
            elsewhere, tmp, tmp);
    ws_image small;
    if (ws_image_alloc(&small, 24, 20, 1, &st) == 0) {
        memset(small.data, 0, sizeof(float) * 24 * 20);
        snprintf(line, sizeof line, "%s/train/r_00005.png", elsewhere);
        ws_png_write(line, &small, &st);
        ws_image_free(&small);
    }
    snprintf(want, sizeof want, "%s/train/r_00005.png: mask is 24 x 20 but its image %s/images/train/r_00005.png is 48 x 40",
             elsewhere, colmap);
    rc = load(&c, colmap, elsewhere, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "a mask of another size: %s", st.msg);
    /* a masks folder beside images/ that has no mask for any image */
    run_cmd(out, sizeof out, "mkdir -p %s/masks/other && cp %s/small.png %s/masks/other/x.png", colmap, tmp, colmap);
    snprintf(want, sizeof want,
             "%s/masks: no mask for any image (tried %s/masks/train/r_00000.png and %s/masks/train/r_00000.png.png for "
             "train/r_00000.png)",
             colmap, colmap, colmap);
    rc = load(&c, colmap, NULL, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "a masks folder for nothing: %s", st.msg);
    /* the command line: check --masks DIR says where the masks came from */
    run_cmd(out, sizeof out, "rm -rf %s/masks && cp %s/r_00005.png %s/train/r_00005.png", colmap, tmp, elsewhere);
    rc = run_cmd(out, sizeof out, "%s check %s --size 32 --masks %s", program_path(), colmap, elsewhere);
    snprintf(want, sizeof want, "%s: masks for 10 of 10 views from %s\n", colmap, elsewhere);
    CHECK(strstr(out, want) != NULL, "check --masks: exit %d: %s", rc, out);
    return check_summary();
}
