/* sort.h: sorting numbers for ranks and medians (percentiles of distances,
 * edge-strength thresholds, point spacings). */
#ifndef WS_BASE_SORT_H
#define WS_BASE_SORT_H
#include <stddef.h>

/* Sorts v[0..n) ascending in place. */
void ws_sort_doubles(double *v, size_t n);

#endif
