/* scene_load.h: a test's synthetic scene, made and loaded the way most
 * tests want it: the synthesis options at one size and view counts, and the
 * scene loaded at size x size with the default options (black background,
 * images loaded). Tests that need other options set them after or instead. */
#ifndef WS_TEST_SCENE_LOAD_H
#define WS_TEST_SCENE_LOAD_H
#include "io/scene.h"
#include "synth/synth.h"

/* The default synthesis options with frames of size x size and train, val
 * and test views. */
static inline void synth_options_at(ws_synth_options *syn, int size, int train, int val, int test) {
    ws_synth_options_default(syn);
    syn->size = size;
    syn->views[WS_TRAIN] = train;
    syn->views[WS_VAL] = val;
    syn->views[WS_TEST] = test;
}

static inline int load_scene_at(ws_scene *scene, const char *dir, int size, ws_status *st) {
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = size;
    return ws_scene_load(scene, dir, &so, st);
}

#endif
