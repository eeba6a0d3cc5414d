/* sort.c: see sort.h. */
#include <stdlib.h>
#include "base/sort.h"

static int compare_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void ws_sort_doubles(double *v, size_t n) { qsort(v, n, sizeof *v, compare_double); }
