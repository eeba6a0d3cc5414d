/* fuzz_png.c: the image loader (ws_image_read: PNG and JPEG, told apart by
 * content), resampling included.
 * Seeds: tests/fuzz/corpus/png (one tiny file of each kind the loader
 * takes: gray, gray+alpha, RGB, RGBA at 8 and 16 bits, palette with and
 * without tRNS, low bit depths, interlaced; JPEG gray, RGB, progressive). */
#include <math.h>
#include "fuzz_input.h"
#include "io/image.h"

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    fuzz_setup("png");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char path[4096];
    fuzz_write("in.png", data, size, path);
    static const float background[3] = {0.25f, 0.5f, 0.75f};
    /* the working size: 12 x 10 (shrinks most inputs, enlarges the 1-pixel
     * ones) */
    ws_image img;
    ws_status st = {0};
    if (ws_image_read(path, 12, 10, background, &img, &st)) {
        fuzz_expect_refusal(&st, WS_EINPUT, path);
        return 0;
    }
    if (img.width != 12 || img.height != 10 || img.channels != 3) abort();
    for (int i = 0; i < 3 * 12 * 10; i++)
        if (!(img.data[i] >= -1e-6f && img.data[i] <= 1 + 1e-6f)) abort();
    ws_image_free(&img);
    return 0;
}
