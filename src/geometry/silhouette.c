/* silhouette.c: silhouettes and their distance maps (see silhouette.h). */
#include <math.h>
#include <stdlib.h>
#include "render/distance.h"
#include "geometry/silhouette.h"

int ws_silhouette_make(const ws_image *photo, const ws_image *mask, ws_silhouette *s,
                       ws_status *st) {
    const int W = photo->width, H = photo->height;
    const size_t hw = (size_t)W * H;
    *s = (ws_silhouette){.width = W, .height = H, .edge_inset = mask ? 0.0 : WS_SILHOUETTE_EDGE_INSET};
    if (mask && (mask->width != W || mask->height != H))
        return ws_fail(st, WS_EINTERNAL, "silhouette: mask %d x %d for a %d x %d photo",
                       mask->width, mask->height, W, H);
    s->in = ws_malloc(hw, "a silhouette", st);
    s->distance = s->in ? ws_malloc(hw * sizeof(float), "a silhouette distance map", st) : NULL;
    float *border = s->distance ? ws_malloc(sizeof(float) * 2 * (W + H), "border pixels", st) : NULL;
    if (!border) {
        ws_silhouette_free(s);
        return st->code;
    }
    float background[3];
    ws_image_border_median(photo, background, border);
    free(border);
    for (size_t p = 0; p < hw; p++) {
        int object;
        if (mask) {
            object = mask->data[p] >= 0.5f;
        } else {
            double diff = 0;
            for (int c = 0; c < 3; c++) diff = fmax(diff, fabs(photo->data[c * hw + p] - background[c]));
            object = diff > WS_SILHOUETTE_THRESHOLD;
        }
        s->in[p] = (uint8_t)object;
        s->area += object;
        int i = (int)(p / W), j = (int)(p % W);
        s->touches_border |= object && (i == 0 || j == 0 || i == H - 1 || j == W - 1);
    }
    if (ws_distance_map(s->in, W, H, s->distance, st)) {
        ws_silhouette_free(s);
        return st->code;
    }
    return WS_OK;
}

int ws_view_silhouette(const ws_view *v, ws_silhouette *s, ws_status *st) {
    return ws_silhouette_make(&v->photo, v->mask.data ? &v->mask : NULL, s, st);
}

void ws_silhouette_free(ws_silhouette *s) {
    free(s->in);
    free(s->distance);
    s->in = NULL;
    s->distance = NULL;
}
