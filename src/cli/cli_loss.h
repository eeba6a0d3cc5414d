/* cli_loss.h: the --loss choice that fit, eval and grad share. */
#ifndef WS_CLI_LOSS_H
#define WS_CLI_LOSS_H
#include "cli/args.h"
#include "objective/loss.h"

/* --loss auto, every command's default: clip+edges when the CLIP weight
 * file exists (the CLIP terms with the edge term, which ranks the ground
 * truth first at every thickness on the three solids, docs/RESULTS.md
 * "Rankings"; the demo's CLIP fit), edges (weight-free) when it does not. */
#define WS_CLI_LOSS_AUTO "clip+edges"

/* The loss `name` stands for: name itself, or for "auto" the choice above. */
const char *ws_cli_auto_loss(const char *name, const char *weights_path);
/* When `name` (as given) is "auto": says which loss it chose and why, on
 * stderr, as the command's first line once its arguments are checked
 * ("wiresketch: --loss auto: edges (no CLIP weight file at W; ...)"). */
void ws_cli_announce_loss(const char *name, const char *weights_path);

/* Sets *precision (a clip_precision) for --precision NAME: fp32, bf16, or
 * auto: bf16 where the CPU has AVX512_BF16, else fp32. */
int ws_cli_choose_precision(const char *name, int *precision, ws_status *st);
/* --hidden-lines TEXT: hull or none, else WS_EUSAGE "--hidden-lines:
 * 'TEXT' is not hull or none". */
int ws_cli_hidden_mode(const char *text, ws_hidden_mode *mode, ws_status *st);

/* Sets lo's term weights for --loss NAME: clip (the CLIP terms as lo has
 * them), edges (the edge loss alone, weight edges_weight), clip+edges,
 * sobel, or l2 (the pixel loss alone); layers (--clip-conv-layer-weights,
 * or NULL), when given, replaces the default layer weights; geometric
 * (--clip-geometric) is blocks or attention, what the geometric term
 * compares; hidden (--hidden-lines) is hull or none, or NULL for the
 * loss's default: hull for the line loss alone (`--loss edges`), none
 * otherwise (CLIP's sketch is see-through, docs/METHOD.md section 6). Then
 * checks that a CLIP weight file exists when a CLIP term is on, with a
 * message that says how to get one and how to run without. */
int ws_cli_choose_loss(const char *name, double edges_weight, const ws_arg_list *layers,
                       const char *geometric, const char *hidden, ws_loss_options *lo, ws_status *st);

#endif
