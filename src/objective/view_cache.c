/* view_cache.c: per-view slots filled once (see view_cache.h). */
#include <stdlib.h>
#include <string.h>
#include "objective/view_cache.h"

int ws_view_cache_init(ws_view_cache *c, const ws_scene *scene, size_t floats_per_view, const char *what,
                       ws_status *st) {
    memset(c, 0, sizeof *c);
    c->floats_per_view = floats_per_view;
    c->what = what;
    for (int s = 0; s < WS_NSPLITS; s++) {
        c->n[s] = scene->split[s].n;
        if (!(c->slot[s] = ws_calloc((size_t)c->n[s], sizeof *c->slot[s], what, st))) return st->code;
    }
    return WS_OK;
}

void ws_view_cache_free(ws_view_cache *c) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        for (int v = 0; c->slot[s] && v < c->n[s]; v++) free(c->slot[s][v]);
        free(c->slot[s]);
    }
    memset(c, 0, sizeof *c);
}

void ws_view_cache_drop(ws_view_cache *c, int split) {
    for (int v = 0; v < c->n[split]; v++) {
        free(c->slot[split][v]);
        c->slot[split][v] = NULL;
    }
}

int ws_view_cache_get(ws_view_cache *c, int split, int view, ws_view_fill fill, void *ctx, const float **out,
                      ws_status *st) {
    float **slot = &c->slot[split][view];
    if (!*slot) {
        float *fresh = ws_malloc(c->floats_per_view * sizeof(float), c->what, st);
        if (!fresh) return st->code;
        if (fill(ctx, split, view, fresh, st)) {
            free(fresh);
            return st->code;
        }
        *slot = fresh;
    }
    *out = *slot;
    return WS_OK;
}

size_t ws_view_cache_full_bytes(const ws_view_cache *c, int split) {
    return (size_t)c->n[split] * c->floats_per_view * sizeof(float);
}
