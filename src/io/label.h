/* label.h: short text drawn into an image (the sweep's contact sheet
 * names its rows), in a 5 x 7 pixel font: lower-case letters (upper case
 * is drawn as lower case), digits, space and = , . _ - + : /; any other
 * character as '?'. Each character advances WS_LABEL_ADVANCE pixels times
 * the scale. */
#ifndef WS_LABEL_H
#define WS_LABEL_H
#include "io/image.h"

#define WS_LABEL_ADVANCE 6
#define WS_LABEL_HEIGHT 7

/* Draws text with its top left at (x, y), each font pixel a scale x scale
 * square of value ink in every channel; what falls outside the image is
 * left out. */
void ws_label_draw(ws_image *img, int x, int y, const char *text, int scale, float ink);

#endif
