/* test_convex_fill.c: render/convex_fill.h against an independent
 * construction: the convex hull of every corner of every pixel of the set
 * by gift wrapping, then each pixel centre tested against each of its
 * edges, all in integers (coordinates doubled), so the two must agree
 * pixel for pixel, centres on the hull's edge included. On random sets
 * (scattered pixels, discs with dents between them) at sizes from 1 x 1
 * to 97 x 64, an empty set, one pixel, two pixels far apart, a full frame.
 * The pixels of the set keep their values and those added are 1. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "nn/base/rng.h"
#include "render/convex_fill.h"

typedef struct {
    long long x, y;
} point;

static long long cross(point o, point a, point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }
static long long dist2(point a, point b) { return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y); }

/* want: 1 where the pixel's centre lies in the closed hull of the set's
 * squares, by gift wrapping over their corners (doubled: 2j, 2i). */
static void reference_fill(const float *mask, int W, int H, unsigned char *want) {
    point *p = malloc(sizeof *p * 4 * (size_t)W * H + sizeof *p), *hull = malloc(sizeof *hull * 4 * (size_t)W * H + sizeof *hull);
    int n = 0, h = 0;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++)
            if (mask[(size_t)i * W + j] > 0.5f)
                for (int c = 0; c < 4; c++) p[n++] = (point){2 * (j + c % 2), 2 * (i + c / 2)};
    memset(want, 0, (size_t)W * H);
    if (n) {
        int start = 0;
        for (int k = 1; k < n; k++)
            if (p[k].y < p[start].y || (p[k].y == p[start].y && p[k].x < p[start].x)) start = k;
        int at = start;
        do {
            hull[h++] = p[at];
            int next = at == 0 ? 1 : 0;
            for (int k = 0; k < n; k++) {
                const long long c = cross(p[at], p[next], p[k]);
                if (c < 0 || (c == 0 && dist2(p[at], p[k]) > dist2(p[at], p[next]))) next = k;
            }
            at = next;
        } while (!(p[at].x == p[start].x && p[at].y == p[start].y) && h < n);
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++) {
                const point c = {2 * j + 1, 2 * i + 1};
                int in = 1;
                for (int e = 0; e < h && in; e++) in = cross(hull[e], hull[(e + 1) % h], c) >= 0;
                want[(size_t)i * W + j] = (unsigned char)in;
            }
    }
    free(p);
    free(hull);
}

/* Fills a copy of mask and compares it with the reference. */
static void check_fill(const float *mask, int W, int H, const char *what) {
    const size_t n = (size_t)W * H;
    float *got = malloc(n * sizeof *got + sizeof *got);
    unsigned char *want = malloc(n + 1);
    memcpy(got, mask, n * sizeof *got);
    reference_fill(mask, W, H, want);
    ws_status st = {0};
    CHECK(ws_convex_fill(got, W, H, &st) == WS_OK, "%s %d x %d: filled", what, W, H);
    size_t differ = 0, kept = 1;
    for (size_t q = 0; q < n; q++) {
        differ += (got[q] > 0.5f) != want[q];
        if (mask[q] > 0.5f) kept &= got[q] == mask[q];
        else if (got[q] > 0.5f) kept &= got[q] == 1;
    }
    CHECK(differ == 0, "%s %d x %d: %zu of %zu pixels differ from the gift-wrapped hull", what, W, H, differ, n);
    CHECK(kept, "%s %d x %d: the set's values kept, 1 where added", what, W, H);
    free(got);
    free(want);
}

int main(void) {
    static const int sizes[][2] = {{1, 1}, {1, 7}, {7, 1}, {2, 2}, {13, 9}, {40, 40}, {97, 64}};
    ws_rng rng;
    ws_rng_seed(&rng, 11);
    for (size_t z = 0; z < sizeof sizes / sizeof *sizes; z++) {
        const int W = sizes[z][0], H = sizes[z][1];
        const size_t n = (size_t)W * H;
        float *mask = calloc(n, sizeof *mask);
        check_fill(mask, W, H, "empty");
        mask[(size_t)(H / 2) * W + W / 3] = 0.75f;
        check_fill(mask, W, H, "one pixel");
        mask[(size_t)(H - 1) * W] = 1;
        check_fill(mask, W, H, "two pixels");
        for (int trial = 0; trial < 6; trial++) {
            const double density = trial < 2 ? 0.02 : 0;
            for (size_t q = 0; q < n; q++) mask[q] = ws_rng_uniform(&rng) < density ? 1 : (float)(0.5 * ws_rng_uniform(&rng));
            for (int disc = 0; trial >= 2 && disc < trial - 1; disc++) { /* discs: a blob with dents between them */
                const double cx = W * ws_rng_uniform(&rng), cy = H * ws_rng_uniform(&rng), r = 0.25 * W * ws_rng_uniform(&rng) + 0.5;
                for (int i = 0; i < H; i++)
                    for (int j = 0; j < W; j++)
                        if ((j + 0.5 - cx) * (j + 0.5 - cx) + (i + 0.5 - cy) * (i + 0.5 - cy) <= r * r)
                            mask[(size_t)i * W + j] = 1;
            }
            check_fill(mask, W, H, trial < 2 ? "scattered pixels" : "discs");
        }
        for (size_t q = 0; q < n; q++) mask[q] = 1;
        check_fill(mask, W, H, "full frame");
        free(mask);
    }
    return check_summary();
}
