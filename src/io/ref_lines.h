/* ref_lines.h: the reference line drawings a sketch is scored against
 * (metrics/drawing_score.h), one pair of files per view in
 * SCENE/lines/SPLIT/ (a scene's own, or written by `wiresketch scene`):
 *   NAME.png        the lines, white (255) on black (0), 1 px wide;
 *   NAME_parts.png  the same lines by kind over the object's mask, RGB:
 *                   background (0,0,0), mask (48,48,48), silhouette
 *                   (255,60,60), inner occluding contour (60,255,60),
 *                   crease (60,160,255).
 * In memory a view is one H x W map of ws_line_part values. Reading checks
 * that every pixel of the parts file has one of the five colours and that
 * the line pixels of the two files (grey >= 128; a line colour) agree. */
#ifndef WS_REF_LINES_H
#define WS_REF_LINES_H
#include <stdint.h>
#include "nn/base/status.h"

typedef enum {
    WS_PART_BACKGROUND = 0,
    WS_PART_MASK,        /* the object, no line */
    WS_PART_SILHOUETTE,  /* its outline against the background */
    WS_PART_CONTOUR,     /* an inner occluding contour */
    WS_PART_CREASE,      /* a sharp edge */
    WS_PART_KINDS
} ws_line_part;

/* Is a pixel of this kind a line? The outline (silhouette or contour)? */
static inline int ws_part_is_line(uint8_t k) { return k >= WS_PART_SILHOUETTE && k < WS_PART_KINDS; }
static inline int ws_part_is_outline(uint8_t k) { return k == WS_PART_SILHOUETTE || k == WS_PART_CONTOUR; }

/* Reads dir/NAME.png and dir/NAME_parts.png into part (H x W), which must
 * be W x H pixels. Every failure names its file: "PATH: 256 x 256 pixels,
 * the view is 224 x 224", "PATH: pixel (row 3, column 5) is (1,2,3), not
 * one of the five part colours", "PATH: pixel (row 3, column 5) is a line
 * in NAME_parts.png but not here" (and the converse). */
int ws_ref_lines_read(const char *dir, const char *name, int W, int H, uint8_t *part, ws_status *st);

/* Writes part (H x W) as dir/NAME.png and dir/NAME_parts.png. */
int ws_ref_lines_write(const char *dir, const char *name, const uint8_t *part, int W, int H, ws_status *st);

#endif
