/* scene_crops.c: the line on a scene's crops (see scene_crops.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "io/scene_crops.h"

void ws_scene_crop_line(const ws_scene *scene, char *line, size_t size) {
    int n = 0, cropped = 0, cw = 0, ch = 0, w = 0, h = 0, same = 1, side_lo = 0, side_hi = 0;
    int reduced = 0, least = 8, most = 1; /* photos decoded smaller, and by how much */
    double off = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            const ws_view *v = &scene->split[s].views[k];
            n++;
            if (v->reduced > 1) {
                reduced++;
                least = v->reduced < least ? v->reduced : least;
                most = v->reduced > most ? v->reduced : most;
            }
            if (v->crop[2] == 0 || (v->crop[2] == v->file_width && v->crop[3] == v->file_height)) continue;
            if (cropped++ == 0)
                cw = v->crop[2], ch = v->crop[3], w = v->file_width, h = v->file_height, side_lo = side_hi = cw;
            same &= v->crop[2] == cw && v->crop[3] == ch && v->file_width == w && v->file_height == h;
            side_lo = v->crop[2] < side_lo ? v->crop[2] : side_lo;
            side_hi = v->crop[2] > side_hi ? v->crop[2] : side_hi;
            off = fmax(off, hypot(v->crop[0] + 0.5 * v->crop[2] - 0.5 * v->file_width,
                                  v->crop[1] + 0.5 * v->crop[3] - 0.5 * v->file_height));
        }
    line[0] = 0;
    char decoded[160] = "";
    if (reduced && least == most)
        snprintf(decoded, sizeof decoded, "%d of %d photos decoded at 1/%d of their size, the pixels the working "
                 "views need", reduced, n, most);
    else if (reduced)
        snprintf(decoded, sizeof decoded, "%d of %d photos decoded at 1/%d to 1/%d of their size, the pixels the "
                 "working views need", reduced, n, least, most);
    if (!cropped) {
        if (reduced) snprintf(line, size, "%.300s: %s", scene->dir, decoded);
        return;
    }
    char across[48];
    if (side_lo == side_hi)
        snprintf(across, sizeof across, "%d px across", side_lo);
    else
        snprintf(across, sizeof across, "%d to %d px across", side_lo, side_hi);
    if (scene->zoomed)
        snprintf(line, size,
                 "%.300s: the working views are crops of their frames zoomed onto the region of interest (%d of %d "
                 "views zoomed, %s, up to %.0f px off the frame's centre)",
                 scene->dir, scene->zoomed, n, across, off);
    else if (same)
        snprintf(line, size,
                 "%.300s: the working views are the %d x %d crops of the %d x %d frames around the object's "
                 "projection (%d of %d views, up to %.0f px off the frame's centre)",
                 scene->dir, cw, ch, w, h, cropped, n, off);
    else
        snprintf(line, size,
                 "%.300s: the working views are crops of their frames around the object's projection (%d of %d "
                 "views, frames of several sizes, up to %.0f px off the frame's centre)",
                 scene->dir, cropped, n, off);
    size_t used = strlen(line);
    if (reduced && used < size) snprintf(line + used, size - used, "; %s", decoded);
}
