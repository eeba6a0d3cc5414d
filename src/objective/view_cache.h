/* view_cache.h: what the loss computes once per view and keeps (the
 * unaugmented photo's CLIP features, a training view's augmentation bank,
 * the photo's edge map): one slot of a fixed size per view, allocated and
 * filled the first time the view asks for it. A slot exists only once it
 * is filled, so "is it ready" has one answer, here. */
#ifndef WS_VIEW_CACHE_H
#define WS_VIEW_CACHE_H
#include <stddef.h>
#include "io/scene.h"
#include "nn/base/status.h"

/* Fills the slot (floats_per_view floats) of view `view` of `split`. */
typedef int (*ws_view_fill)(void *ctx, int split, int view, float *slot, ws_status *st);

typedef struct {
    size_t floats_per_view;
    const char *what;                /* for an out-of-memory message */
    int n[WS_NSPLITS];               /* views per split */
    float **slot[WS_NSPLITS];        /* per view: NULL until filled */
} ws_view_cache;

/* A cache for the scene's views, holding nothing yet. */
int ws_view_cache_init(ws_view_cache *c, const ws_scene *scene, size_t floats_per_view, const char *what,
                       ws_status *st);
void ws_view_cache_free(ws_view_cache *c);

/* Frees the filled slots of `split`: each is filled again on its next use. */
void ws_view_cache_drop(ws_view_cache *c, int split);

/* *out: the slot of view `view` of `split`, filled by fill(ctx, ...) on the
 * first call (a failed fill leaves no slot: the next call tries again). */
int ws_view_cache_get(ws_view_cache *c, int split, int view, ws_view_fill fill, void *ctx, const float **out,
                      ws_status *st);

/* Bytes the slots of `split` take once every view has been filled. */
size_t ws_view_cache_full_bytes(const ws_view_cache *c, int split);

#endif
