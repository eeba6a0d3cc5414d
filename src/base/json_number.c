/* json_number.c: JSON numbers, never NaN or Inf (see json_number.h). */
#include <math.h>
#include "base/json_number.h"

void ws_json_number(FILE *fp, const char *key, double v, int digits) {
    if (isfinite(v))
        fprintf(fp, "\"%s\": %.*g", key, digits, v);
    else
        fprintf(fp, "\"%s\": null, \"%s_why\": \"the value is %s, which JSON cannot hold\"", key, key,
                isnan(v) ? "nan" : v > 0 ? "inf" : "-inf");
}

int ws_json_value(FILE *fp, double v, int digits) {
    if (isfinite(v)) {
        fprintf(fp, "%.*g", digits, v);
        return 0;
    }
    fputs("null", fp);
    return 1;
}
