/* cli_loss.c: the --loss choice (see cli_loss.h). */
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "cli/cli_loss.h"
#include "nn/clip.h"
#include "nn/gemm_bf16.h"

int ws_cli_choose_precision(const char *name, int *precision, ws_status *st) {
    if (!strcmp(name, "fp32") || !strcmp(name, "bf16"))
        *precision = !strcmp(name, "bf16") ? CLIP_BF16 : CLIP_FP32;
    else if (!strcmp(name, "auto"))
        *precision = nn_bf16_available() ? CLIP_BF16 : CLIP_FP32;
    else
        return ws_fail(st, WS_EUSAGE, "--precision: '%s' is not fp32, bf16 or auto", name);
    return WS_OK;
}

int ws_cli_choose_loss(const char *name, double edges_weight, const ws_arg_list *layers,
                       const char *geometric, const char *hidden, ws_loss_options *lo, ws_status *st) {
    if (!strcmp(geometric, "blocks"))
        lo->geometric = WS_GEOMETRIC_BLOCKS;
    else if (!strcmp(geometric, "attention"))
        lo->geometric = WS_GEOMETRIC_ATTENTION;
    else
        return ws_fail(st, WS_EUSAGE, "--clip-geometric: '%s' is not blocks or attention", geometric);
    if (layers && layers->n) {
        lo->n_layer_weights = layers->n;
        memset(lo->layer_weights, 0, sizeof lo->layer_weights);
        memcpy(lo->layer_weights, layers->v, layers->n * sizeof(double));
    }
    int clip = !strcmp(name, "clip") || !strcmp(name, "clip+edges");
    if (!clip) lo->conv_weight = lo->fc_weight = lo->global_weight = 0;
    if (!strcmp(name, "edges") || !strcmp(name, "clip+edges"))
        lo->lines_weight = edges_weight;
    else if (!strcmp(name, "sobel"))
        lo->edges_weight = edges_weight;
    else if (!strcmp(name, "l2"))
        lo->l2_weight = 1.0;
    else if (!clip)
        return ws_fail(st, WS_EUSAGE, "--loss: '%s' is not clip, edges, clip+edges, sobel or l2", name);
    if (!hidden)
        lo->hidden_lines = lo->lines_weight != 0 && !ws_loss_uses_clip(lo) ? WS_HIDDEN_HULL : WS_HIDDEN_NONE;
    else if (ws_cli_hidden_mode(hidden, &lo->hidden_lines, st))
        return st->code;
    if (ws_loss_uses_clip(lo) && access(lo->weights_path, R_OK) != 0)
        return ws_fail(st, WS_EINPUT,
                       "%s: no CLIP weight file; convert OpenAI's ViT-B-32.pt once with "
                       "`python3 tools/convert_weights.py ViT-B-32.pt %s` (see weights/README.md), "
                       "or run without CLIP: --loss edges",
                       lo->weights_path, lo->weights_path);
    return WS_OK;
}

int ws_cli_hidden_mode(const char *text, ws_hidden_mode *mode, ws_status *st) {
    if (strcmp(text, "hull") && strcmp(text, "none"))
        return ws_fail(st, WS_EUSAGE, "--hidden-lines: '%s' is not hull or none", text);
    *mode = !strcmp(text, "hull") ? WS_HIDDEN_HULL : WS_HIDDEN_NONE;
    return WS_OK;
}

const char *ws_cli_auto_loss(const char *name, const char *weights_path) {
    if (strcmp(name, "auto") != 0) return name;
    return access(weights_path, R_OK) == 0 ? WS_CLI_LOSS_AUTO : "edges";
}

void ws_cli_announce_loss(const char *name, const char *weights_path) {
    if (strcmp(name, "auto") != 0) return;
    if (access(weights_path, R_OK) == 0)
        fprintf(stderr, "wiresketch: --loss auto: %s (the CLIP weight file %s exists)\n", WS_CLI_LOSS_AUTO,
                weights_path);
    else
        fprintf(stderr, "wiresketch: --loss auto: edges (no CLIP weight file at %s; weights/README.md says how "
                        "to make one for CLIP)\n", weights_path);
}
