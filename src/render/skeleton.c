/* skeleton.c: Zhang-Suen thinning (see skeleton.h). */
#include <stdlib.h>
#include <string.h>
#include "render/skeleton.h"

/* One sub-passes' removals of set into gone (1 = remove); returns how many. */
static size_t mark(const uint8_t *set, int W, int H, int second, uint8_t *gone) {
    size_t count = 0;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            size_t p = (size_t)i * W + j;
            gone[p] = 0;
            if (!set[p]) continue;
            /* P2..P9: N, NE, E, SE, S, SW, W, NW */
            static const int di[8] = {-1, -1, 0, 1, 1, 1, 0, -1}, dj[8] = {0, 1, 1, 1, 0, -1, -1, -1};
            int n[8], b = 0, a = 0;
            for (int k = 0; k < 8; k++) {
                int ii = i + di[k], jj = j + dj[k];
                n[k] = ii >= 0 && ii < H && jj >= 0 && jj < W && set[(size_t)ii * W + jj];
                b += n[k];
            }
            for (int k = 0; k < 8; k++) a += !n[k] && n[(k + 1) % 8];
            if (b < 2 || b > 6 || a != 1) continue;
            int p2 = n[0], p4 = n[2], p6 = n[4], p8 = n[6];
            if (!second ? (p2 && p4 && p6) || (p4 && p6 && p8) : (p2 && p4 && p8) || (p2 && p6 && p8)) continue;
            gone[p] = 1;
            count++;
        }
    return count;
}

int ws_skeleton_thin(uint8_t *set, int W, int H, ws_status *st) {
    const size_t n = (size_t)W * H;
    uint8_t *gone = ws_malloc(n ? n : 1, "thinning", st);
    if (!gone) return st->code;
    for (size_t p = 0; p < n; p++) set[p] = set[p] != 0;
    for (;;) {
        size_t removed = 0;
        for (int second = 0; second < 2; second++) {
            size_t k = mark(set, W, H, second, gone);
            for (size_t p = 0; k && p < n; p++) set[p] &= !gone[p];
            removed += k;
        }
        if (!removed) break;
    }
    free(gone);
    return WS_OK;
}
