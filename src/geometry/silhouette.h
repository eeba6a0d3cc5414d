/* silhouette.h: which pixels of a view show the object.
 *
 * A view's silhouette is its mask where the scene gives one (a mask_path
 * image, or a PNG alpha channel that is not opaque everywhere); otherwise
 * the pixels whose photo differs from the background colour by more than
 * WS_SILHOUETTE_THRESHOLD in some channel:
 *     object(i, j) = max_c |photo_c(i, j) - background_c| > 0.02
 * on the working-size photo (values in [0, 1], so 0.02 is about 5 / 255:
 * above the 1 / 255 noise of a rendered black background, below any lit
 * surface). The background colour is the per-channel median of the pixels
 * on the photo's border (black and white backgrounds alike; an object
 * covering less than half of the border does not move it). Alongside it, the Euclidean distance in pixels from every pixel
 * centre to the nearest object pixel centre, which the visual hull uses to
 * test a whole voxel against the silhouette at once. */
#ifndef WS_SILHOUETTE_H
#define WS_SILHOUETTE_H
#include <stdint.h>
#include "io/image.h"
#include "io/scene.h"
#include "nn/base/status.h"

#define WS_SILHOUETTE_THRESHOLD 0.02
/* What a point projected near a silhouette may miss it by and still be on
 * the object: half a pixel's diagonal twice, once for the pixel centre the
 * distance is read at, once for the silhouette pixel's own extent. */
#define WS_SILHOUETTE_PIXEL_SLACK 1.42
/* A photo's edge pixel is object from a few percent of cover up, so the
 * object's edge lies about halfway across it, at its centre. */
#define WS_SILHOUETTE_EDGE_INSET 0.5

typedef struct {
    int width, height;
    uint8_t *in;        /* height x width: 1 = object */
    float *distance;    /* height x width: pixels to the nearest object pixel, 0 on it;
                           INFINITY everywhere when the silhouette is empty */
    int touches_border; /* an object pixel lies on the image's edge: the object may go on
                           beyond the frame */
    long area;          /* object pixels */
    double edge_inset;  /* how far inside the object pixels' outer edges the object's edge lies,
                           pixels: WS_SILHOUETTE_EDGE_INSET from the photo, where a pixel the
                           object covers only in part is object already; 0 from a mask, which
                           holds the pixels it covers at least half */
} ws_silhouette;

/* From `mask` (1 x H x W, >= 1/2 = object) when it is not NULL, else from
 * the photo (3 x H x W) against its background as above. */
int ws_silhouette_make(const ws_image *photo, const ws_image *mask, ws_silhouette *s,
                       ws_status *st);
/* A view's silhouette: from its mask where the scene gives one (scene.h),
 * else from its photo. */
int ws_view_silhouette(const ws_view *v, ws_silhouette *s, ws_status *st);
void ws_silhouette_free(ws_silhouette *s);

#endif
