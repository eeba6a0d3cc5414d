/* cli_loss.h: the --loss choice that fit, eval and grad share. */
#ifndef WS_CLI_LOSS_H
#define WS_CLI_LOSS_H
#include "cli/args.h"
#include "objective/loss.h"

/* Sets lo's term weights for --loss NAME: clip (the CLIP terms as lo has
 * them), edges (the edge loss alone, weight edges_weight), clip+edges, or
 * l2 (the pixel loss alone); layers (--clip-conv-layer-weights, or NULL),
 * when given, replaces the default layer weights; geometric
 * (--clip-geometric) is blocks or attention, what the geometric term
 * compares; hidden (--hidden-lines) is hull or none, or NULL for the
 * loss's default: hull for the line loss alone (`--loss edges`), none
 * otherwise (CLIP's sketch is see-through, SPEC sections 3 and 6). Then
 * checks that a CLIP weight file exists when a CLIP term is on, with a
 * message that says how to get one and how to run without. */
/* --clip-geometric's help, the same in every command that takes it. */
#define WS_CLI_GEOMETRIC_HELP \
    "what CLIP's geometric term compares: blocks (outputs h_l) or attention (probabilities P_l) [blocks]"

/* --hidden-lines's help, the same in every command that takes it. */
#define WS_CLI_HIDDEN_HELP \
    "hidden-line removal of the stroke images: hull (drawn only where the visual hull does not hide them) " \
    "or none [hull with --loss edges, none otherwise]"

/* --precision's help, the same in every command that takes it. */
#define WS_CLI_PRECISION_HELP                                                                        \
    "CLIP's weight GEMMs: fp32, bf16 (CPUs with AVX512_BF16; gradient error below the augmentations' " \
    "own noise, docs/RESULTS.md) or auto (bf16 where the CPU has it) [auto]"

/* Sets *precision (a clip_precision) for --precision NAME: fp32, bf16, or
 * auto: bf16 where the CPU has AVX512_BF16, else fp32. */
int ws_cli_choose_precision(const char *name, int *precision, ws_status *st);

int ws_cli_choose_loss(const char *name, double edges_weight, const ws_arg_list *layers,
                       const char *geometric, const char *hidden, ws_loss_options *lo, ws_status *st);

#endif
