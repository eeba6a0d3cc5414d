/* scene_crops.h: one line saying what the working views' crops of a scene
 * did (io/view_crop.h), for the commands that load a scene to print. */
#ifndef WS_IO_SCENE_CROPS_H
#define WS_IO_SCENE_CROPS_H
#include <stddef.h>
#include "io/scene.h"

/* "" when every view is its whole frame; else e.g. "SCENE: the working
 * views are the 216 x 216 crops of the 288 x 216 frames around the object's
 * projection (64 of 64 views, up to 36 px off the frame's centre)", or
 * "SCENE: the working views are crops of their frames zoomed onto the
 * region of interest (64 of 64 views zoomed, 301 to 355 px across, up to
 * 120 px off the frame's centre)" (scene.h: zoomed), followed by "; 64 of
 * 64 photos decoded at 1/4 of their size, the pixels the working views
 * need" where large photos were read smaller (scene.h: reduced). */
void ws_scene_crop_line(const ws_scene *scene, char *line, size_t size);

#endif
