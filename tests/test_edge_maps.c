/* test_edge_maps.c: users' own edge maps (`--edge-maps DIR`, a frame's
 * edge_path; scene.h) replace the thin edges in the line loss: they load
 * resampled to the working size, the loss compares the strokes with them,
 * and a missing one is an error naming what was tried. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "scene_load.h"
#include "check.h"
#include "test_util.h"
#include "io/image.h"
#include "objective/loss.h"
#include "synth/synth.h"

/* A 128 x 128 gray PNG with one bright row at y = 64. */
static void write_map(const char *path) {
    ws_status st;
    ws_image m = {0};
    ws_image_alloc(&m, 128, 128, 3, &st);
    memset(m.data, 0, sizeof(float) * 3 * 128 * 128);
    for (int c = 0; c < 3; c++)
        for (int j = 0; j < 128; j++) m.data[(c * 128 + 64) * 128 + j] = 1;
    CHECK(ws_png_write(path, &m, &st) == WS_OK, "%s: %s", path, st.msg);
    ws_image_free(&m);
}

/* The scene at 64 px with these options; checks view 0 of the test split
 * has an edge map of one bright row (rows 31-32 after resampling) and
 * that the line loss scores strokes on that row 0 and elsewhere more. */
static void check_loaded(const char *dir, const char *edge_maps, const char *what) {
    ws_status st;
    ws_scene sc;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 64;
    so.edge_maps_dir = edge_maps;
    int rc = ws_scene_load(&sc, dir, &so, &st);
    CHECK(rc == WS_OK, "%s: %s", what, st.msg);
    if (rc) return;
    const ws_view *v = &sc.split[WS_TEST].views[0];
    CHECK(v->edges.data && v->edges.width == 64 && v->edges.channels == 1, "%s: no 64 px edge map", what);
    if (v->edges.data) {
        double on = 0, off = 0;
        for (int j = 0; j < 64; j++) {
            on += v->edges.data[32 * 64 + j] + v->edges.data[31 * 64 + j];
            off += v->edges.data[10 * 64 + j];
        }
        CHECK(on > 20 && off == 0, "%s: the map's row is not where it was drawn (%g, %g)", what, on, off);
        ws_loss_options lo;
        ws_loss_options_default(&lo);
        lo.conv_weight = lo.fc_weight = lo.global_weight = 0;
        lo.lines_weight = 1;
        ws_loss *loss = NULL;
        double alpha[64 * 64], l_on, l_off;
        rc = ws_loss_create(&loss, &lo, &sc, &st);
        for (int p = 0; p < 64 * 64; p++) alpha[p] = v->edges.data[p];
        rc = rc || ws_loss_view(loss, WS_TEST, 0, alpha, 0, NULL, &l_on, NULL, &st);
        memset(alpha, 0, sizeof alpha);
        for (int j = 0; j < 64; j++) alpha[10 * 64 + j] = 1;
        rc = rc || ws_loss_view(loss, WS_TEST, 0, alpha, 0, NULL, &l_off, NULL, &st);
        CHECK(rc == WS_OK && l_on < 1e-6 && l_off > 0.5, "%s: loss on the map %g, off it %g (%s)", what, l_on,
              l_off, st.msg);
        ws_loss_free(loss);
    }
    ws_scene_free(&sc);
}

int main(void) {
    const char *tmp = test_tmpdir("edge_maps");
    char dir[300], maps[300], path[700];
    ws_status st;
    ws_synth_options syn;
    synth_options_at(&syn, 64, 1, 0, 1);
    snprintf(dir, sizeof dir, "%s/scene", tmp);
    CHECK(ws_synth_write("cube", dir, &syn, &st) == WS_OK, "scene: %s", st.msg);
    /* --edge-maps DIR: DIR/<file_path>.png, here 128 px for 64 px photos */
    snprintf(maps, sizeof maps, "%s/maps", tmp);
    mkdir(maps, 0777);
    snprintf(path, sizeof path, "%s/train", maps);
    mkdir(path, 0777);
    snprintf(path, sizeof path, "%s/test", maps);
    mkdir(path, 0777);
    snprintf(path, sizeof path, "%s/test/r_0.png", maps);
    write_map(path);
    ws_scene sc;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 64;
    so.edge_maps_dir = maps;
    char want[2000];
    snprintf(want, sizeof want,
             "%s/transforms_train.json: frame 0: --edge-maps: image not found (tried %s/train/r_0.png, %s/rgb/train/r_0.png)",
             dir, maps, maps);
    int rc = ws_scene_load(&sc, dir, &so, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want), "missing map: %s", st.msg);
    if (!rc) ws_scene_free(&sc);
    snprintf(path, sizeof path, "%s/train/r_0.png", maps);
    write_map(path);
    check_loaded(dir, maps, "--edge-maps");
    /* a frame's edge_path, relative to the scene */
    snprintf(path, sizeof path, "%s/em.png", dir);
    write_map(path);
    snprintf(path, sizeof path, "%s/transforms_test.json", dir);
    FILE *f = fopen(path, "rb");
    static char text[1 << 16], edited[1 << 16];
    size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
    if (f) fclose(f);
    text[n] = '\0';
    char *at = strstr(text, "\"file_path\"");
    CHECK(at != NULL, "no file_path in %s", path);
    if (at) {
        snprintf(edited, sizeof edited, "%.*s\"edge_path\": \"em.png\", %s", (int)(at - text), text, at);
        f = fopen(path, "wb");
        fputs(edited, f);
        fclose(f);
        check_loaded(dir, NULL, "edge_path");
    }
    return check_summary();
}
