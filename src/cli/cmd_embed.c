/* cmd_embed.c: `wiresketch embed`: CLIP image embeddings of PNG files, one
 * JSON array per image and line, in the order given (%.9g: float exact).
 * Images are read at the model's resolution on a black background. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli/args.h"
#include "nn/clip.h"
#include "cli/cli_view.h"
#include "cli/commands.h"
#include "io/image.h"

/* Images per forward pass: batched GEMMs, bounded memory. */
#define EMBED_BATCH 8

/* Embeds paths[0..n) with a run of batch `batch`: chunk by chunk. */
static int embed_files(const clip_model *m, const char *const *paths, int n, ws_status *st) {
    const wf_arch *a = clip_model_arch(m);
    int batch = n < EMBED_BATCH ? n : EMBED_BATCH, R = a->resolution;
    size_t image = (size_t)3 * R * R;
    static const float black[3] = {0, 0, 0};
    clip_run *run = NULL;
    clip_run_options opt = {batch, a->layers - 1, 1, 0, 0};
    float *images = ws_calloc((size_t)batch * image, sizeof *images, "embed images", st);
    if (!images || clip_run_create(&run, m, &opt, st)) {
        free(images);
        return st->code;
    }
    for (int first = 0; first < n && !st->code; first += batch) {
        int count = n - first < batch ? n - first : batch;
        for (int k = 0; k < count && !st->code; k++) {
            ws_image img;
            if (!ws_image_read(paths[first + k], R, R, black, &img, st)) {
                memcpy(images + k * image, img.data, image * sizeof *images);
                ws_image_free(&img);
            }
        }
        if (st->code || clip_forward(run, images, st)) break;
        const float *e = clip_embedding(run);
        for (int k = 0; k < count; k++) {
            for (int j = 0; j < a->output_dim; j++)
                printf("%s%.9g", j ? ", " : "[", e[(size_t)k * a->output_dim + j]);
            printf("]\n");
        }
        if (ws_cli_stdout_check(st)) break; /* no more work for a reader that is gone */
    }
    clip_run_free(run);
    free(images);
    return st->code;
}

int cmd_embed(int argc, char **argv) {
    const char *weights = NULL;
    const ws_arg args[] = {
        {"--weights", WS_ARG_STRING, &weights, 0, "CLIP weight file (weights/README.md)"},
    };
    const ws_command_spec spec = {
        "embed --weights FILE IMAGE.png...",
        "Print the CLIP embedding of each image as a JSON array, one line per image.",
        args, sizeof args / sizeof args[0], 1, 1 << 20, NULL, 0};
    int argc_max = argc > 0 ? argc : 1;
    const char **pos = malloc((size_t)argc_max * sizeof *pos);
    ws_status st;
    ws_status_clear(&st);
    if (!pos) {
        ws_fail(&st, WS_ENOMEM, "out of memory for the argument list");
        return ws_cli_fail(&st);
    }
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) {
        free(pos);
        return done;
    }
    clip_model *m = NULL;
    if (!ws_cli_require(weights, "--weights", &st) && !clip_model_load(&m, weights, &st)) embed_files(m, pos, npos, &st);
    clip_model_free(m);
    free(pos);
    return st.code ? ws_cli_fail(&st) : 0;
}
