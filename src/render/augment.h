/* augment.h: the random augmentation of METHOD.md section 5.
 *
 * One transform is a random perspective warp followed by a random resized
 * crop, with the semantics of torchvision 0.14 (tensor images):
 *   RandomPerspective(distortion_scale=0.5, p=1, fill=0, bilinear), then
 *   RandomResizedCrop(size=(H, W), scale=(0.8, 0.8), ratio=(1, 1), bilinear).
 * The stroke image and the photo of a view get the same ws_aug_params, so
 * the caller draws one transform and applies it to both.
 *
 * Exactly as torchvision (and verified against it, tests/test_augment.c):
 * - corners: the image corners (0,0), (W-1,0), (W-1,H-1), (0,H-1) move to
 *   integer end points, each coordinate uniform over the torchvision range
 *   (top-left x in [0, floor(0.5 * floor(W/2))], top-right x in
 *   [W - 1 - floor(0.5 * floor(W/2)), W - 1], likewise for y);
 * - the homography maps end points to start points (output to source) and
 *   is evaluated at pixel centres (j + 0.5, i + 0.5); the source is sampled
 *   bilinearly as grid_sample(align_corners=False, padding zeros): source
 *   pixel coordinate = homography(j + 0.5, i + 0.5) - 0.5;
 * - fill 0 goes through torchvision's mask: the warped image is multiplied
 *   by the warp of an all-ones image, so pixels whose bilinear footprint is
 *   partly outside the source are darkened once more (out = m * sum w v with
 *   m = the in-bounds share of the footprint);
 * - crop side round(sqrt(0.8 * W * H)) (round half to even, with 0.8 as the
 *   float32 that torch draws), top-left uniform over all positions; when that
 *   square does not fit (aspect beyond 1.25), the centred min(W,H) square;
 * - resize back to W x H: bilinear, align_corners=False, source coordinate
 *   clamped at 0, no antialias (the crop is smaller than the image, so this
 *   is always an enlargement).
 * Randomness comes from ws_rng, not torch's generator: the distribution of
 * the transforms is torchvision's, the stream of numbers is not.
 *
 * Both resamplings are linear in the image, so the backward pass is the
 * exact transpose; it is computed per channel as a scatter in a fixed order
 * (deterministic for any thread count). */
#ifndef WS_AUGMENT_H
#define WS_AUGMENT_H
#include "nn/base/rng.h"
#include "nn/base/status.h"

#define WS_AUG_DISTORTION 0.5
#define WS_AUG_CROP_SCALE 0.8

/* One drawn transform: plain data (a checkpoint can store it as bytes). */
typedef struct {
    int width, height;     /* image size it was drawn for */
    int corner[4][2];      /* (x, y) where the corners top-left, top-right,
                              bottom-right, bottom-left of the image go */
    int crop_top, crop_left, crop_height, crop_width;
    double homography[8];  /* derived from corner[]: output (x, y) to source
                              ((h0 x + h1 y + h2) / (h6 x + h7 y + 1),
                               (h3 x + h4 y + h5) / (h6 x + h7 y + 1)) */
} ws_aug_params;

/* Sets a transform from given corner end points and crop box (for tests and
 * for replaying a stored transform). Fails with WS_EINPUT when the box is
 * not inside the image or the corners make a degenerate quadrilateral. */
int ws_aug_params_init(ws_aug_params *p, int width, int height, const int corner[4][2],
                       int crop_top, int crop_left, int crop_height, int crop_width,
                       ws_status *st);

/* Draws a transform as torchvision's get_params do. Fails with WS_EINPUT
 * for images smaller than 2 x 2. */
int ws_aug_sample(ws_aug_params *p, ws_rng *rng, int width, int height, ws_status *st);

/* Buffers for images up to width x height with up to `channels` channels. */
typedef struct ws_aug_workspace ws_aug_workspace;

int ws_aug_workspace_create(ws_aug_workspace **ws, int width, int height, int channels,
                            ws_status *st);
void ws_aug_workspace_free(ws_aug_workspace *ws);

/* in, out: C x H x W planar (image.h layout); out is overwritten and must
 * not alias in. H and W must be the size p was drawn for (WS_EINTERNAL
 * otherwise, as for a workspace that is too small). */
int ws_aug_forward(const ws_aug_params *p, const float *in, int C, int H, int W, float *out,
                   ws_aug_workspace *ws, ws_status *st);

/* din = A^T dout for the forward's linear map A; dout, din: C x H x W,
 * din overwritten. Needs no state of a forward pass. */
int ws_aug_backward(const ws_aug_params *p, const float *dout, int C, int H, int W, float *din,
                    ws_aug_workspace *ws, ws_status *st);

#endif
