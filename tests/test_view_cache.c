/* test_view_cache.c: the loss's per-view cache (objective/view_cache.h):
 * a slot is filled once, on first use, per (split, view); a failed fill
 * leaves no slot and is tried again; the full size counts every view; a
 * dropped split's slots are filled again. */
#include <string.h>
#include "check.h"
#include "objective/view_cache.h"

typedef struct {
    int calls;
    int fail; /* the next fill fails */
} counter;

/* Writes (split, view, call number) into the slot's 3 floats. */
static int fill(void *ctx, int split, int view, float *slot, ws_status *st) {
    counter *c = ctx;
    c->calls++;
    if (c->fail) {
        c->fail = 0;
        return ws_fail(st, WS_EINPUT, "fill failed for view %d", view);
    }
    slot[0] = (float)split;
    slot[1] = (float)view;
    slot[2] = (float)c->calls;
    return WS_OK;
}

int main(void) {
    ws_status st = {0};
    ws_scene scene;
    memset(&scene, 0, sizeof scene);
    scene.split[WS_TRAIN].n = 3;
    scene.split[WS_TEST].n = 2;
    ws_view_cache cache;
    counter n = {0, 0};
    CHECK(ws_view_cache_init(&cache, &scene, 3, "test slots", &st) == WS_OK, "init: %s", st.msg);
    const float *a = NULL, *b = NULL, *t = NULL;
    CHECK(ws_view_cache_get(&cache, WS_TRAIN, 2, fill, &n, &a, &st) == WS_OK && a[0] == WS_TRAIN && a[1] == 2 &&
              a[2] == 1,
          "first use fills the slot");
    CHECK(ws_view_cache_get(&cache, WS_TRAIN, 2, fill, &n, &b, &st) == WS_OK && b == a && n.calls == 1 &&
              b[2] == 1,
          "second use reads the slot: %d fills", n.calls);
    CHECK(ws_view_cache_get(&cache, WS_TEST, 1, fill, &n, &t, &st) == WS_OK && t != a && t[0] == WS_TEST &&
              n.calls == 2,
          "another split's view has its own slot");
    n.fail = 1;
    const float *c = NULL;
    CHECK(ws_view_cache_get(&cache, WS_TRAIN, 0, fill, &n, &c, &st) == WS_EINPUT &&
              !strcmp(st.msg, "fill failed for view 0") && cache.slot[WS_TRAIN][0] == NULL,
          "a failed fill leaves no slot: %s", st.msg);
    ws_status_clear(&st);
    CHECK(ws_view_cache_get(&cache, WS_TRAIN, 0, fill, &n, &c, &st) == WS_OK && n.calls == 4 && c[2] == 4,
          "a failed fill is tried again");
    CHECK(ws_view_cache_full_bytes(&cache, WS_TRAIN) == 3 * 3 * sizeof(float) &&
              ws_view_cache_full_bytes(&cache, WS_VAL) == 0,
          "full bytes: %zu", ws_view_cache_full_bytes(&cache, WS_TRAIN));
    ws_view_cache_drop(&cache, WS_TRAIN);
    CHECK(cache.slot[WS_TRAIN][0] == NULL && cache.slot[WS_TRAIN][2] == NULL && cache.slot[WS_TEST][1] == t,
          "a dropped split keeps no slot, another split keeps its own");
    CHECK(ws_view_cache_get(&cache, WS_TRAIN, 2, fill, &n, &a, &st) == WS_OK && n.calls == 5 && a[2] == 5,
          "a dropped slot is filled again on its next use");
    ws_view_cache_free(&cache);
    return check_summary();
}
