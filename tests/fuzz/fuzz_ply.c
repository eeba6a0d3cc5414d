/* fuzz_ply.c: the PLY point-cloud reader (ws_pointcloud_load_ply) that
 * `eval --gt` and the fit's metrics use on gt_points.ply.
 * Seeds: tests/fuzz/corpus/ply (ascii and binary of both byte orders, with
 * extra properties, lists and a face element). */
#include <math.h>
#include "fuzz_input.h"
#include "io/pointcloud.h"

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    fuzz_setup("ply");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char path[4096];
    fuzz_write("in.ply", data, size, path);
    ws_pointcloud pc;
    ws_status st = {0};
    if (ws_pointcloud_load_ply(path, &pc, &st)) {
        fuzz_expect_refusal(&st, WS_EINPUT, path);
        return 0;
    }
    if (pc.n < 1) abort();
    for (int i = 0; i < pc.n * 3; i++)
        if (!isfinite(pc.xyz[i])) abort();
    ws_pointcloud_free(&pc);
    return 0;
}
