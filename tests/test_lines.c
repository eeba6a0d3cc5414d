/* test_lines.c: the thin edge target (thin_edges.h) and the line loss
 * (lines.h): the loss against a naive implementation of its definition, its
 * gradient against central finite differences (double) at several points of
 * the coarse-to-fine schedule, its invariances, and the edge map's
 * one-pixel width and independence of contrast. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "reference_pyramid.h"
#include "nn/base/rng.h"
#include "objective/lines.h"
#include "render/thin_edges.h"

/* lines.h written out the slow way: explicit pyramid, 2-D kernel. */
static double reference(const double *alpha, const float *edge, int W, int H, const double w[]) {
    double *img[2], *blur[2], *next = malloc((size_t)W * H * sizeof *next);
    for (int m = 0; m < 2; m++) {
        img[m] = malloc((size_t)W * H * sizeof(double));
        blur[m] = malloc((size_t)W * H * sizeof(double));
        for (int p = 0; p < W * H; p++) img[m][p] = m ? edge[p] : alpha[p];
    }
    int ww = W, hh = H;
    double loss = 0, wsum = 0;
    for (int s = 0; s < WS_LINES_LEVELS; s++) {
        if (s > 0) {
            for (int m = 0; m < 2; m++) {
                ref_pool(img[m], ww, hh, next);
                memcpy(img[m], next, (size_t)((ww + 1) / 2) * ((hh + 1) / 2) * sizeof(double));
            }
            ww = (ww + 1) / 2, hh = (hh + 1) / 2;
        }
        for (int m = 0; m < 2; m++) ref_blur(img[m], ww, hh, WS_LINES_SIGMA, blur[m]);
        double ae = 0, aa = 0, ee = 0, eps = WS_LINES_EPS * ww * hh;
        for (int p = 0; p < ww * hh; p++) {
            ae += blur[0][p] * blur[1][p];
            aa += blur[0][p] * blur[0][p];
            ee += blur[1][p] * blur[1][p];
        }
        loss += w[s] * (1 - ae / (sqrt(aa + eps) * sqrt(ee + eps)));
        wsum += w[s];
    }
    for (int m = 0; m < 2; m++) {
        free(img[m]);
        free(blur[m]);
    }
    free(next);
    return loss / wsum;
}

static void test_schedule(void) {
    double w[WS_LINES_LEVELS];
    ws_lines_weights(0, w);
    CHECK(w[0] == 0 && w[1] == 0 && w[2] == 0 && w[3] == 1, "p = 0: %g %g %g %g", w[0], w[1], w[2], w[3]);
    ws_lines_weights(0.25, w);
    CHECK(w[0] == 0 && w[1] == 0.5 && w[2] == 1 && w[3] == 1, "p = 0.25: %g %g %g %g", w[0], w[1], w[2], w[3]);
    ws_lines_weights(WS_LINES_COARSE_END, w);
    CHECK(w[0] == 1 && w[1] == 1 && w[2] == 1 && w[3] == 1, "p = 0.5: %g %g %g %g", w[0], w[1], w[2], w[3]);
    ws_lines_weights(7, w);
    CHECK(w[0] == 1 && w[3] == 1, "p clamped");
}

/* Random strokes and a random thin target on a W x H image (odd sizes: the
 * pooling's border cells). */
static void test_loss_and_gradient(int W, int H, double progress, uint64_t seed) {
    ws_status st;
    ws_rng rng;
    ws_rng_seed(&rng, seed);
    size_t n = (size_t)W * H;
    double *alpha = malloc(n * sizeof *alpha), *dalpha = malloc(n * sizeof *dalpha), w[WS_LINES_LEVELS];
    float *edge = malloc(n * sizeof *edge);
    for (size_t p = 0; p < n; p++) {
        alpha[p] = ws_rng_uniform(&rng) < 0.3 ? ws_rng_uniform(&rng) : 0;
        edge[p] = ws_rng_uniform(&rng) < 0.1;
    }
    ws_lines_weights(progress, w);
    ws_lines_workspace *ws = NULL;
    if (ws_lines_workspace_create(&ws, W, H, &st)) {
        CHECK(0, "workspace: %s", st.msg);
        return;
    }
    double loss = ws_lines_loss(alpha, edge, w, ws, dalpha);
    double ref = reference(alpha, edge, W, H, w);
    CHECK(check_close(loss, ref, 1e-12, 1e-12), "%dx%d p %g: loss %.15g, naive %.15g", W, H, progress, loss, ref);
    CHECK(ws_lines_loss(alpha, edge, w, ws, NULL) == loss, "the loss alone differs from the loss with gradient");
    double worst = 0, gmax = 0;
    for (size_t p = 0; p < n; p++) gmax = fmax(gmax, fabs(dalpha[p]));
    for (size_t p = 0; p < n; p++) {
        double keep = alpha[p], h = 1e-6;
        alpha[p] = keep + h;
        double up = ws_lines_loss(alpha, edge, w, ws, NULL);
        alpha[p] = keep - h;
        double down = ws_lines_loss(alpha, edge, w, ws, NULL);
        alpha[p] = keep;
        double fd = (up - down) / (2 * h);
        worst = fmax(worst, fabs(fd - dalpha[p]) / gmax);
    }
    CHECK(worst < 1e-6, "%dx%d p %g: finite differences off by %.2g of the largest entry", W, H, progress, worst);
    printf("line loss %dx%d at p %.2f: %.6g, worst fd error %.1e of the largest entry\n", W, H, progress, loss, worst);
    /* scale-free: the loss of 3 A is the loss of A (up to eps_s) */
    for (size_t p = 0; p < n; p++) alpha[p] *= 3;
    double scaled = ws_lines_loss(alpha, edge, w, ws, NULL);
    CHECK(check_close(scaled, loss, 1e-7, 1e-12), "scaling the strokes changes the loss: %.17g, %.17g", scaled, loss);
    /* strokes exactly on the target: 0; no strokes: 1, the worst, with a finite gradient */
    for (size_t p = 0; p < n; p++) alpha[p] = edge[p];
    CHECK(fabs(ws_lines_loss(alpha, edge, w, ws, NULL)) < 1e-9, "strokes on the target do not score 0");
    memset(alpha, 0, n * sizeof *alpha);
    double empty = ws_lines_loss(alpha, edge, w, ws, dalpha);
    int finite = 1;
    for (size_t p = 0; p < n; p++) finite &= isfinite(dalpha[p]);
    CHECK(empty == 1 && finite, "empty sketch: loss %.17g, finite gradient %d", empty, finite);
    ws_lines_workspace_free(ws);
    free(alpha);
    free(dalpha);
    free(edge);
}

/* A vertical step of luminance lo | hi at column 20 of a 48 x 40 photo. */
static void step_photo(float *photo, int W, int H, float lo, float hi) {
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++) photo[(c * H + i) * W + j] = j < 20 ? lo : hi;
}

static void test_thin_edges(void) {
    const int W = 48, H = 40;
    ws_status st;
    float *photo = malloc(3 * W * H * sizeof *photo), *e = malloc(W * H * sizeof *e),
          *e2 = malloc(W * H * sizeof *e2);
    step_photo(photo, W, H, 0.2f, 0.8f);
    CHECK(ws_thin_edges(photo, W, H, e, &st) == WS_OK, "step: %s", st.msg);
    int one_wide = 1, total = 0;
    for (int i = 0; i < H; i++) {
        int row = 0;
        for (int j = 0; j < W; j++) {
            row += e[i * W + j] == 1;
            total += e[i * W + j] != 0;
        }
        one_wide &= row == 1 && (e[i * W + 19] == 1 || e[i * W + 20] == 1);
    }
    CHECK(one_wide && total == H, "step: not one pixel per row at the step (%d edge pixels)", total);
    /* the same map at a tenth of the contrast */
    step_photo(photo, W, H, 0.5f, 0.56f);
    CHECK(ws_thin_edges(photo, W, H, e2, &st) == WS_OK && !memcmp(e, e2, W * H * sizeof *e),
          "a step of contrast 0.06 gives another map than one of 0.6");
    /* a weak crease beside a strong silhouette survives: a bright square
     * (0.8) on black whose right half is a little darker (0.7) */
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++)
                photo[(c * H + i) * W + j] = i < 8 || i >= 32 || j < 8 || j >= 40 ? 0 : j < 24 ? 0.8f : 0.7f;
    ws_thin_edges(photo, W, H, e, &st);
    int crease = 0, stray = 0;
    for (int i = 12; i < 28; i++) crease += e[i * W + 23] == 1 || e[i * W + 24] == 1;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            int near_edge = (abs(i - 8) <= 1 || abs(i - 31) <= 1 || abs(j - 8) <= 1 || abs(j - 39) <= 1 ||
                             abs(j - 23) <= 1 || abs(j - 24) <= 1);
            stray += e[i * W + j] == 1 && !near_edge;
        }
    CHECK(crease == 16 && stray == 0, "crease beside a silhouette: %d of 16 crease rows, %d stray pixels", crease, stray);
    /* a mask's outline: the object pixels beside background ones */
    float *mask = malloc(W * H * sizeof *mask);
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) mask[i * W + j] = i >= 10 && i < 30 && j >= 12 && j < 36;
    memset(e, 0, W * H * sizeof *e);
    ws_thin_edges_add_outline(mask, W, H, e);
    int ring = 0, wrong = 0;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            int on = mask[i * W + j] && (i == 10 || i == 29 || j == 12 || j == 35);
            ring += on && e[i * W + j] == 1;
            wrong += !on && e[i * W + j] != 0;
        }
    CHECK(ring == 2 * 20 + 2 * 24 - 4 && wrong == 0, "mask outline: %d of 84 ring pixels, %d others", ring, wrong);
    free(mask);
    /* no gradient, no edges */
    step_photo(photo, W, H, 0.3f, 0.3f);
    ws_thin_edges(photo, W, H, e, &st);
    int any = 0;
    for (int p = 0; p < W * H; p++) any |= e[p] != 0;
    CHECK(!any, "a flat photo has edges");
    free(photo);
    free(e);
    free(e2);
}

int main(void) {
    test_schedule();
    test_loss_and_gradient(29, 23, 1.0, 1);
    test_loss_and_gradient(32, 17, 0.0, 2);
    test_loss_and_gradient(15, 20, 0.3, 3);
    test_thin_edges();
    return check_summary();
}
