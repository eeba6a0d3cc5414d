/* clip_model.c: the public interface's CLIP model, nn/clip.h's under the
 * library's ws_ names. */
#include "objective/clip_model.h"
#include "nn/clip.h"

int ws_clip_model_load(ws_clip_model **m, const char *path, ws_status *st) {
    return clip_model_load(m, path, st);
}

void ws_clip_model_free(ws_clip_model *m) {
    clip_model_free(m);
}

int ws_clip_model_resolution(const ws_clip_model *m) {
    return clip_model_arch(m)->resolution;
}
