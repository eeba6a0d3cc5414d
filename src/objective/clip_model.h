/* clip_model.h: the CLIP model as a program that embeds wiresketch holds
 * it: loaded once from a weight file (weights/README.md) and lent to any
 * number of losses (ws_loss_options.model), which otherwise load their own
 * from ws_loss_options.weights_path. The layout and the tower's own calls
 * stay inside nn/ (nn/clip.h); this is the whole of CLIP in the public
 * interface (wiresketch.h). */
#ifndef WS_CLIP_MODEL_H
#define WS_CLIP_MODEL_H
#include "nn/base/status.h"

typedef struct clip_model ws_clip_model;

/* A file that is missing, truncated or malformed is refused with one line
 * naming it (nn/weightfile.h). */
int ws_clip_model_load(ws_clip_model **m, const char *path, ws_status *st);
void ws_clip_model_free(ws_clip_model *m);
/* The side of the model's square input images, px: a scene fitted with a
 * CLIP term is loaded at this size (ws_scene_options.size). */
int ws_clip_model_resolution(const ws_clip_model *m);

#endif
