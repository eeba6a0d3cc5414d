/* view_spread.c: train views spread over their directions (see view_spread.h). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include "geometry/view_spread.h"

void ws_view_direction(const ws_camera *cam, const double centre[3], double e[3]) {
    double len = 0;
    ws_camera_position(cam, e);
    for (int a = 0; a < 3; a++) e[a] -= centre[a], len += e[a] * e[a];
    for (int a = 0; a < 3; a++) e[a] = len > 0 ? e[a] / sqrt(len) : 0;
}

int ws_view_spread(const ws_split *train, const double centre[3], int most, const ws_view **views, int *n,
                   ws_status *st) {
    const int all = train->n, m = all < most ? all : most;
    *n = m;
    if (m == all) {
        for (int v = 0; v < all; v++) views[v] = &train->views[v];
        return WS_OK;
    }
    double *dir = ws_malloc(sizeof *dir * 3 * (size_t)all, "view spread", st);
    double *nearest = dir ? ws_malloc(sizeof *nearest * (size_t)all, "view spread", st) : NULL; /* cosine */
    uint8_t *chosen = nearest ? ws_calloc((size_t)all, 1, "view spread", st) : NULL;
    if (!chosen) {
        free(dir);
        free(nearest);
        return st->code;
    }
    for (int v = 0; v < all; v++) {
        ws_view_direction(&train->views[v].cam, centre, dir + 3 * v);
        nearest[v] = -INFINITY;
    }
    for (int c = 0, pick = 0; c < m; c++) {
        chosen[pick] = 1;
        const double *a = dir + 3 * pick;
        for (int w = 0; w < all; w++)
            nearest[w] = fmax(nearest[w], a[0] * dir[3 * w] + a[1] * dir[3 * w + 1] + a[2] * dir[3 * w + 2]);
        pick = -1;
        for (int w = 0; w < all; w++)
            if (!chosen[w] && (pick < 0 || nearest[w] < nearest[pick])) pick = w;
    }
    for (int v = 0, c = 0; v < all; v++)
        if (chosen[v]) views[c++] = &train->views[v];
    free(dir);
    free(nearest);
    free(chosen);
    return WS_OK;
}
