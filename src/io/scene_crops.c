/* scene_crops.c: the line on a scene's crops (see scene_crops.h). */
#include <math.h>
#include <stdio.h>
#include "io/scene_crops.h"

void ws_scene_crop_line(const ws_scene *scene, char *line, size_t size) {
    int n = 0, cropped = 0, cw = 0, ch = 0, w = 0, h = 0, same = 1;
    double off = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            const ws_view *v = &scene->split[s].views[k];
            n++;
            if (v->crop[2] == 0 || (v->crop[2] == v->file_width && v->crop[3] == v->file_height)) continue;
            if (cropped++ == 0) cw = v->crop[2], ch = v->crop[3], w = v->file_width, h = v->file_height;
            same &= v->crop[2] == cw && v->crop[3] == ch && v->file_width == w && v->file_height == h;
            off = fmax(off, hypot(v->crop[0] + 0.5 * v->crop[2] - 0.5 * v->file_width,
                                  v->crop[1] + 0.5 * v->crop[3] - 0.5 * v->file_height));
        }
    line[0] = 0;
    if (!cropped) return;
    if (same)
        snprintf(line, size,
                 "%.300s: the working views are the %d x %d crops of the %d x %d frames around the object's "
                 "projection (%d of %d views, up to %.0f px off the frame's centre)",
                 scene->dir, cw, ch, w, h, cropped, n, off);
    else
        snprintf(line, size,
                 "%.300s: the working views are crops of their frames around the object's projection (%d of "
                 "%d views, frames of several sizes, up to %.0f px off the frame's centre)",
                 scene->dir, cropped, n, off);
}
