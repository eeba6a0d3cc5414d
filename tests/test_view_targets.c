/* test_view_targets.c: each view's silhouette and line target, made once
 * and shared (objective/view_targets.h). On a 64 px cube: the silhouettes
 * and line targets are bit for bit those made directly
 * (ws_view_silhouette, ws_line_target), a second request returns the same
 * buffers instead of making them again, a view with its own edge map gets
 * that map, and what the setup alone reads, once released, is made again
 * the same while the training silhouettes stay. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_util.h"
#include "objective/line_target.h"
#include "objective/view_targets.h"
#include "scene_load.h"
#include "synth/synth.h"

enum { SIZE = 64 };

static int same_silhouette(const ws_silhouette *a, const ws_silhouette *b) {
    size_t hw = (size_t)SIZE * SIZE;
    return a->width == b->width && a->height == b->height && a->area == b->area &&
           a->touches_border == b->touches_border && !memcmp(a->in, b->in, hw) &&
           !memcmp(a->distance, b->distance, hw * sizeof(float));
}

int main(void) {
    const char *tmp = test_tmpdir("view_targets");
    char dir[300];
    ws_status st;
    ws_synth_options syn;
    synth_options_at(&syn, SIZE, 6, 2, 0);
    snprintf(dir, sizeof dir, "%s/cube", tmp);
    ws_scene scene;
    ws_view_targets *t = NULL;
    int rc = ws_synth_write("cube", dir, &syn, &st);
    if (!rc) rc = load_scene_at(&scene, dir, SIZE, &st);
    if (!rc) rc = ws_view_targets_create(&t, &scene, &st);
    CHECK(rc == WS_OK, "setup: %s", st.msg);
    if (rc) return check_summary();
    const size_t hw = (size_t)SIZE * SIZE;

    /* the line target of a view whose silhouette nobody asked for yet */
    const float *line, *again;
    ws_silhouette fresh;
    float *direct = malloc(hw * sizeof *direct);
    const ws_view *v = &scene.split[WS_VAL].views[1];
    CHECK(ws_view_targets_line(t, WS_VAL, 1, &line, &st) == WS_OK && ws_view_silhouette(v, &fresh, &st) == WS_OK &&
              ws_line_target(&v->photo, NULL, &fresh, NULL, direct, &st) == WS_OK,
          "line target: %s", st.msg);
    CHECK(!memcmp(line, direct, hw * sizeof *line), "the shared line target is not ws_line_target's");
    CHECK(ws_view_targets_line(t, WS_VAL, 1, &again, &st) == WS_OK && again == line,
          "a second request made the line target again");
    ws_silhouette_free(&fresh);

    /* the silhouettes of a split: the same bits, the same buffers the second time */
    const ws_silhouette *sil, *sil2;
    CHECK(ws_view_targets_silhouettes(t, WS_TRAIN, &sil, &st) == WS_OK, "silhouettes: %s", st.msg);
    const uint8_t *in[6];
    int same = 1;
    for (int k = 0; k < scene.split[WS_TRAIN].n; k++) {
        in[k] = sil[k].in;
        CHECK(ws_view_silhouette(&scene.split[WS_TRAIN].views[k], &fresh, &st) == WS_OK, "silhouette: %s", st.msg);
        same &= same_silhouette(&sil[k], &fresh) && sil[k].area > 0;
        ws_silhouette_free(&fresh);
    }
    CHECK(same, "a shared silhouette is not ws_view_silhouette's (or is empty)");
    CHECK(ws_view_targets_silhouettes(t, WS_TRAIN, &sil2, &st) == WS_OK && sil2 == sil, "silhouettes again: %s",
          st.msg);
    int kept = 1;
    for (int k = 0; k < scene.split[WS_TRAIN].n; k++) kept &= sil2[k].in == in[k];
    CHECK(kept, "a second request made the silhouettes again");

    /* a view with its own edge map: that map, as given */
    ws_view *own = &scene.split[WS_TRAIN].views[2];
    CHECK(ws_image_alloc(&own->edges, SIZE, SIZE, 1, &st) == WS_OK, "edge map: %s", st.msg);
    for (size_t p = 0; p < hw; p++) own->edges.data[p] = (float)(p % 7) / 7;
    CHECK(ws_view_targets_line(t, WS_TRAIN, 2, &line, &st) == WS_OK &&
              !memcmp(line, own->edges.data, hw * sizeof *line),
          "a view's own edge map is not its line target");

    /* released: line targets and validation silhouettes made again, the same */
    ws_view_targets_release_setup(t);
    v = &scene.split[WS_VAL].views[1];
    CHECK(ws_view_targets_line(t, WS_VAL, 1, &line, &st) == WS_OK && !memcmp(line, direct, hw * sizeof *line),
          "a released line target is not made again the same: %s", st.msg);
    CHECK(ws_view_targets_silhouettes(t, WS_VAL, &sil2, &st) == WS_OK && ws_view_silhouette(v, &fresh, &st) == WS_OK &&
              same_silhouette(&sil2[1], &fresh),
          "a released silhouette is not made again the same: %s", st.msg);
    ws_silhouette_free(&fresh);
    CHECK(ws_view_targets_silhouettes(t, WS_TRAIN, &sil2, &st) == WS_OK, "silhouettes: %s", st.msg);
    kept = 1;
    for (int k = 0; k < scene.split[WS_TRAIN].n; k++) kept &= sil2[k].in == in[k];
    CHECK(kept, "the release freed the training silhouettes");

    free(direct);
    ws_view_targets_free(t);
    ws_scene_free(&scene);
    return check_summary();
}
