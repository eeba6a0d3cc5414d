/* fuzz_scene.c: the scene loader (ws_scene_load) on a fuzzed
 * transforms_train.json. The scene directory holds tiny valid PNGs at
 * train/r_0.png .. train/r_2.png, so that frames naming them reach the
 * camera, path and image stages. Seeds: tests/fuzz/corpus/scene (the rose
 * scene's transforms cut down to a few frames, and variants). */
#include <math.h>
#include "fuzz_input.h"
#include "base/outfile.h"
#include "io/scene.h"

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    fuzz_setup("scene");
    char path[4096];
    snprintf(path, sizeof path, "%s/train", fuzz_dir);
    ws_status st = {0};
    ws_image img;
    if (ws_mkdir(path, &st) || ws_image_alloc(&img, 4, 3, 3, &st)) abort();
    for (int i = 0; i < 4 * 3 * 3; i++) img.data[i] = (float)(i % 7) / 6.0f;
    for (int k = 0; k < 3; k++) {
        snprintf(path, sizeof path, "%s/train/r_%d.png", fuzz_dir, k);
        if (ws_png_write(path, &img, &st)) abort();
    }
    ws_image_free(&img);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char path[4096];
    fuzz_write("transforms_train.json", data, size, path);
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = opt.height = 8;
    ws_scene scene;
    ws_status st = {0};
    if (ws_scene_load(&scene, fuzz_dir, &opt, &st)) {
        fuzz_expect_refusal(&st, WS_EINPUT, fuzz_dir);
        return 0;
    }
    if (scene.split[WS_TRAIN].n < 1) abort();
    for (int i = 0; i < 3; i++)
        if (!isfinite(scene.center[i])) abort();
    ws_scene_free(&scene);
    return 0;
}
