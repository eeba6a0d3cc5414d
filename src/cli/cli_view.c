/* cli_view.c: shared scene/split/view options (see cli_view.h). */
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include "cli/cli_view.h"
#include "geometry/roi.h"


int ws_cli_require(const char *value, const char *option, ws_status *st) {
    if (!value) return ws_fail(st, WS_EUSAGE, "%s: required (see --help)", option);
    return WS_OK;
}

/* The largest --size any command takes (pixels a side). */
#define MAX_SIZE 4096

int ws_cli_check_size(int size, ws_status *st) {
    if (size < 1 || size > MAX_SIZE)
        return ws_fail(st, WS_EUSAGE, "--size: %d is not in [1, %d]", size, MAX_SIZE);
    return WS_OK;
}

int ws_cli_background(const char *text, float rgb[3], int *is_auto, ws_status *st) {
    double v[3];
    char tail;
    *is_auto = !strcmp(text, "auto");
    if (!strcmp(text, "black") || !strcmp(text, "white") || *is_auto) {
        rgb[0] = rgb[1] = rgb[2] = !strcmp(text, "white") ? 1.0f : 0.0f;
        return WS_OK;
    }
    if (sscanf(text, "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) == 3 && v[0] >= 0 && v[0] <= 1 &&
        v[1] >= 0 && v[1] <= 1 && v[2] >= 0 && v[2] <= 1) {
        for (int c = 0; c < 3; c++) rgb[c] = (float)v[c];
        return WS_OK;
    }
    return ws_fail(st, WS_EUSAGE, "--background: '%s' is not black, white, auto or R,G,B in [0, 1]",
                   text);
}

int ws_cli_load_split(const char *dir, int size, int load_images, const char *background,
                      const char *split_name, ws_scene *scene, int *split, ws_status *st) {
    if (ws_cli_check_size(size, st)) return st->code;
    *split = ws_split_index(split_name);
    if (*split < 0)
        return ws_fail(st, WS_EUSAGE, "--split: '%s' is not train, val or test", split_name);
    ws_scene_options opt;
    ws_scene_options_default(&opt);
    opt.width = opt.height = size;
    opt.load_images = load_images;
    if (background && ws_cli_background(background, opt.background, &opt.background_auto, st))
        return st->code;
    if (ws_roi_load_scene(scene, dir, &opt, NULL, NULL, NULL, st)) return st->code;
    if (scene->split[*split].n == 0) {
        ws_scene_free(scene);
        return ws_fail(st, WS_EINPUT, "%s: no %s split (transforms_%s.json)", dir, split_name,
                       split_name);
    }
    return WS_OK;
}

int ws_cli_check_view(const ws_scene *scene, int split, int view, ws_status *st) {
    int n = scene->split[split].n;
    if (view < 0 || view >= n)
        return ws_fail(st, WS_EUSAGE, "--view: %d is not in [0, %d] (the %s split has %d views)",
                       view, n - 1, ws_split_names[split], n);
    return WS_OK;
}
