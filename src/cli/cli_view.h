/* cli_view.h: the scene/split/view options that render, grad and export
 * share: checking them and loading what they name, with the same messages
 * everywhere. */
#ifndef WS_CLI_VIEW_H
#define WS_CLI_VIEW_H
#include "io/scene.h"
#include "nn/base/status.h"

/* Fails with WS_EUSAGE "--size: N is not in [1, 4096]" for a working
 * resolution no command takes. */
int ws_cli_check_size(int size, ws_status *st);

/* Fails with WS_EUSAGE "OPTION: required" when value is NULL. */
int ws_cli_require(const char *value, const char *option, ws_status *st);

/* --background TEXT: "black", "white", "auto" (each image's border
 * median: *is_auto = 1) or "R,G,B" with each in [0, 1]; WS_EUSAGE
 * "--background: 'TEXT' is not black, white, auto or R,G,B in [0, 1]". */
int ws_cli_background(const char *text, float rgb[3], int *is_auto, ws_status *st);
#define WS_CLI_MASKS_HELP \
    "folder of the views' masks (DIR/<image name> as .png; white = object) [SCENE/masks, nerfstudio and COLMAP]"
#define WS_CLI_BACKGROUND_HELP \
    "photo background: black, white, auto (the image border's median) or R,G,B in [0, 1] [black]"

/* Loads `dir` at size x size (images only if load_images, on the
 * --background `background`, NULL for black) and finds split `split_name`,
 * which must have views: *split gets its index. */
int ws_cli_load_split(const char *dir, int size, int load_images, const char *background,
                      const char *split_name, ws_scene *scene, int *split, ws_status *st);

/* Checks that view index `view` exists in split `split` of scene. */
int ws_cli_check_view(const ws_scene *scene, int split, int view, ws_status *st);

#endif
