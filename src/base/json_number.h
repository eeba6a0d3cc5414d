/* json_number.h: the numbers of the JSON files and lines wiresketch writes
 * itself (metrics.json, eval's line, grad's gradient).
 *
 * JSON has no NaN or infinity, and a reader refuses the whole file for
 * one: a non-finite value is written as null, with the reason beside it
 * (KEY_why), so that the file stays valid and says what happened. */
#ifndef WS_JSON_NUMBER_H
#define WS_JSON_NUMBER_H
#include <stdio.h>

/* `"KEY": V` (V with `digits` significant digits), or for a non-finite V
 * `"KEY": null, "KEY_why": "the value is inf, which JSON cannot hold"`. */
void ws_json_number(FILE *fp, const char *key, double v, int digits);
/* V alone (an array's item): null when not finite; returns 1 then, so
 * that the caller can say how many were. */
int ws_json_value(FILE *fp, double v, int digits);

#endif
