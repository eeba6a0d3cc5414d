/* ref_lines.c: the reference line files (see ref_lines.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "base/paths.h"
#include "io/image.h"
#include "io/ref_lines.h"

static const int PART_RGB[WS_PART_KINDS][3] = {
    {0, 0, 0}, {48, 48, 48}, {255, 60, 60}, {60, 255, 60}, {60, 160, 255}};

/* Reads PATH at its own size into img, checking that it is W x H. */
static int read_exact(const char *path, int W, int H, ws_image *img, ws_status *st) {
    const float black[3] = {0, 0, 0};
    if (ws_image_read(path, 0, 0, black, img, st)) return st->code;
    if (img->width != W || img->height != H) {
        int w = img->width, h = img->height;
        ws_image_free(img);
        return ws_fail(st, WS_EINPUT, "%s: %d x %d pixels, the view is %d x %d", path, w, h, W, H);
    }
    return WS_OK;
}

int ws_ref_lines_read(const char *dir, const char *name, int W, int H, uint8_t *part, ws_status *st) {
    char lines_path[WS_PATH_MAX], parts_path[WS_PATH_MAX];
    snprintf(lines_path, sizeof lines_path, "%s/%s.png", dir, name);
    snprintf(parts_path, sizeof parts_path, "%s/%s_parts.png", dir, name);
    ws_image lines = {0}, parts = {0};
    if (read_exact(lines_path, W, H, &lines, st) || read_exact(parts_path, W, H, &parts, st)) {
        ws_image_free(&lines);
        return st->code;
    }
    const size_t plane = (size_t)W * H;
    int rc = WS_OK;
    for (size_t p = 0; p < plane && !rc; p++) {
        int rgb[3], kind = -1;
        for (int c = 0; c < 3; c++) rgb[c] = (int)lroundf(255 * parts.data[c * plane + p]);
        for (int k = 0; k < WS_PART_KINDS && kind < 0; k++)
            if (rgb[0] == PART_RGB[k][0] && rgb[1] == PART_RGB[k][1] && rgb[2] == PART_RGB[k][2]) kind = k;
        int row = (int)(p / W), col = (int)(p % W);
        if (kind < 0) {
            rc = ws_fail(st, WS_EINPUT, "%s: pixel (row %d, column %d) is (%d,%d,%d), not one of the five part colours",
                         parts_path, row, col, rgb[0], rgb[1], rgb[2]);
            break;
        }
        int line = lines.data[p] >= 0.5f; /* grey >= 128 of 255 */
        if (line != ws_part_is_line((uint8_t)kind))
            rc = ws_fail(st, WS_EINPUT, "%s: pixel (row %d, column %d) is %s line in %s_parts.png but %s here",
                         lines_path, row, col, line ? "not a" : "a", name, line ? "is one" : "not");
        part[p] = (uint8_t)kind;
    }
    ws_image_free(&lines);
    ws_image_free(&parts);
    return rc;
}

int ws_ref_lines_write(const char *dir, const char *name, const uint8_t *part, int W, int H, ws_status *st) {
    char path[WS_PATH_MAX];
    const size_t plane = (size_t)W * H;
    ws_image lines = {0}, parts = {0};
    if (ws_image_alloc(&lines, W, H, 1, st) || ws_image_alloc(&parts, W, H, 3, st)) {
        ws_image_free(&lines);
        return st->code;
    }
    for (size_t p = 0; p < plane; p++)
        if (part[p] >= WS_PART_KINDS) {
            ws_image_free(&lines);
            ws_image_free(&parts);
            return ws_fail(st, WS_EINTERNAL, "reference lines %s: part %d is no kind", name, part[p]);
        }
    for (size_t p = 0; p < plane; p++) {
        int k = part[p];
        lines.data[p] = (float)ws_part_is_line((uint8_t)k);
        for (int c = 0; c < 3; c++) parts.data[c * plane + p] = PART_RGB[k][c] / 255.0f;
    }
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    int rc = ws_png_write(path, &lines, st);
    snprintf(path, sizeof path, "%s/%s_parts.png", dir, name);
    if (!rc) rc = ws_png_write(path, &parts, st);
    ws_image_free(&lines);
    ws_image_free(&parts);
    return rc;
}
