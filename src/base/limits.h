/* limits.h: how much work and memory an input or an option may ask for.
 *
 * Every size that multiplies (pixels by channels, cells by runs by views,
 * curves by Gaussians) is checked here before anything is allocated, with
 * one line naming what asked for it and the limit it passes, instead of an
 * allocation of terabytes or an overflowed count. */
#ifndef WS_LIMITS_H
#define WS_LIMITS_H
#include <stddef.h>
#include "nn/base/status.h"

/* Frames of a scene file: each view holds its paths (14.5 KB) before any
 * pixel, and the hull and `check` compare every view with the others. */
#define WS_MAX_VIEWS 10000
/* Curves in a curve file (and --n-curves): far more than a sketch shows. */
#define WS_MAX_CURVES 100000
/* Gaussians one sampling of a sketch may make, all splatted into every view:
 * 4 per pixel of a 1024 x 1024 view (a fit of 25 curves makes about a
 * thousand). Thin, long or many curves past it are refused, not rendered
 * for hours. */
#define WS_MAX_GAUSSIANS (1 << 22)
/* Bytes one image may take while it is decoded (its samples and its float
 * planes): a 4096 x 4096 RGBA photo of 16 bits takes 0.4 GiB. Views decode
 * in parallel, one per thread, so a load peaks at threads times this. */
#define WS_MAX_DECODE_BYTES ((size_t)1 << 30)

/* *bytes = the product of the n factors (each >= 0); fails (WS_EINPUT)
 * with "WHAT: A x B x ... = N bytes, more than the LIMIT a ... may take"
 * when it passes limit or overflows, `limit_what` naming what the limit is
 * for ("a view's decoded image"). */
int ws_size_product(const char *what, const size_t *factors, int n, size_t limit, const char *limit_what,
                    size_t *bytes, ws_status *st);

#endif
