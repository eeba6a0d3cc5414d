/* limits.c: the checked size product (see limits.h). */
#include <stdint.h>
#include <stdio.h>
#include "base/limits.h"

int ws_size_product(const char *what, const size_t *factors, int n, size_t limit, const char *limit_what,
                    size_t *bytes, ws_status *st) {
    size_t product = 1;
    int over = 0;
    for (int k = 0; k < n; k++) {
        if (factors[k] != 0 && product > SIZE_MAX / factors[k]) over = 1;
        product = over ? SIZE_MAX : product * factors[k];
    }
    if (over || product > limit) {
        char text[200] = "";
        int at = 0;
        for (int k = 0; k < n && at < (int)sizeof text - 24; k++)
            at += snprintf(text + at, sizeof text - at, "%s%zu", k ? " x " : "", factors[k]);
        if (over)
            return ws_fail(st, WS_EINPUT, "%s: %s bytes overflow; %s may take at most %zu", what, text,
                           limit_what, limit);
        return ws_fail(st, WS_EINPUT, "%s: %s = %zu bytes, more than the %zu %s may take", what, text, product,
                       limit, limit_what);
    }
    *bytes = product;
    return WS_OK;
}
