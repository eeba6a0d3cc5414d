/* scene_load.h: a test's scene, loaded at size x size with the default
 * options (black background, images loaded), the way most tests want it.
 * Tests that need other options set ws_scene_options themselves. */
#ifndef WS_TEST_SCENE_LOAD_H
#define WS_TEST_SCENE_LOAD_H
#include "io/scene.h"

static inline int load_scene_at(ws_scene *scene, const char *dir, int size, ws_status *st) {
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = size;
    return ws_scene_load(scene, dir, &so, st);
}

#endif
