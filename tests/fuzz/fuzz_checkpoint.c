/* fuzz_checkpoint.c: the checkpoint loader (ws_checkpoint_load) that
 * `fit --resume` runs. The checksum is made right before each load
 * (fuzz_fix_crc) so that mutations reach the fields behind it.
 * Seeds: tests/fuzz/corpus/checkpoint (checkpoints of short fits). */
#include <math.h>
#include "fit/checkpoint.h"
#include "fuzz_input.h"

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    fuzz_setup("checkpoint");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char path[4096];
    uint8_t *fixed = fuzz_fix_crc(data, size);
    fuzz_write("checkpoint.bin", fixed, size, path);
    free(fixed);
    ws_fit_state s;
    int argc;
    char **argv;
    ws_status st = {0};
    if (ws_checkpoint_load(path, &s, &argc, &argv, &st)) {
        fuzz_expect_refusal(&st, WS_EINPUT, path);
        if (argc != 0 || argv != NULL) abort();
        return 0;
    }
    /* what a resumed fit relies on */
    if (s.curves.n < 1 || !(s.curves.thickness > 0) || s.n_train < 0) abort();
    for (int i = 0; i < s.curves.n * WS_CURVE_FLOATS; i++)
        if (!isfinite(s.curves.P[i])) abort();
    for (int i = 0; i < s.n_train; i++)
        if (s.order[i] < 0 || s.order[i] >= s.n_train) abort();
    for (int i = 0; i < argc; i++)
        if (!argv[i]) abort();
    ws_fit_state_free(&s);
    ws_checkpoint_free_args(argc, argv);
    return 0;
}
