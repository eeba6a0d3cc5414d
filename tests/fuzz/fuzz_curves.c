/* fuzz_curves.c: the curve-file parser (ws_curves_load) and what every
 * reader of a curve file does next, sampling it into Gaussians.
 * Seeds: tests/fuzz/corpus/curves. */
#include <math.h>
#include "render/curves.h"
#include "fuzz_input.h"

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    fuzz_setup("curves");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char path[4096];
    fuzz_write("in.json", data, size, path);
    ws_curves c;
    ws_status st = {0};
    if (ws_curves_load(path, &c, &st)) {
        fuzz_expect_refusal(&st, WS_EINPUT, path);
        if (c.n != 0 || c.P != NULL) abort();
        return 0;
    }
    for (int k = 0; k < c.n * WS_CURVE_FLOATS; k++)
        if (!isfinite(c.P[k])) abort();
    if (!(c.thickness > 0) || !(c.overlap >= 0 && c.overlap < 1)) abort();
    /* A curve too long to measure was refused by the loader, naming the
     * file: a loaded file samples, and every Gaussian is finite. */
    ws_gaussians g = {0};
    if (ws_curves_sample(&c, &g, &st)) abort();
    for (int k = 0; k < g.n * 3; k++)
        if (!isfinite(g.mu[k])) abort();
    for (int k = 0; k < g.n; k++)
        if (!(g.t[k] >= 0 && g.t[k] <= 1) || g.curve[k] < 0 || g.curve[k] >= c.n) abort();
    ws_gaussians_free(&g);
    ws_curves_free(&c);
    return 0;
}
