/* fuzz_weights.c: the CLIP weight-file loader, as `fit` and `embed` use it:
 * clip_model_load opens the file (nn/weightfile.c checks the header, the
 * table, the checksum and the values) and looks up every tensor of the
 * architecture the header announces. The checksum is made right before
 * each load (fuzz_fix_crc) so that mutations reach the table and values.
 * Seeds: tests/fuzz/corpus/weights (tiny f32 and f16 models from
 * tools/make_fuzz_corpus.py). */
#include <math.h>
#include "nn/clip.h"
#include "fuzz_input.h"

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    fuzz_setup("weights");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char path[4096];
    uint8_t *fixed = fuzz_fix_crc(data, size);
    fuzz_write("in.bin", fixed, size, path);
    free(fixed);
    clip_model *m;
    ws_status st = {0};
    if (clip_model_load(&m, path, &st)) {
        fuzz_expect_refusal(&st, WS_EINPUT, path);
        return 0;
    }
    const wf_arch *a = clip_model_arch(m);
    if (a->width < 1 || a->layers < 1 || a->heads < 1 || a->width % a->heads || a->patch < 1 ||
        a->resolution % a->patch)
        abort();
    clip_model_free(m);
    return 0;
}
