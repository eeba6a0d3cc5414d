/* cli_rows.h: the option rows that several commands take, each declared
 * here once, so that an option reads the same (one help text; one
 * placeholder, args.c) in every command that has it. WS_ROW_X(dest) is the
 * ws_arg of option X whose value goes to dest; a command's table lists it
 * where its own rows would stand. */
#ifndef WS_CLI_ROWS_H
#define WS_CLI_ROWS_H
#include "cli/args.h"
#include "cli/cli_loss.h"

/* What the views are and how they are drawn. */
#define WS_ROW_SIZE(dest)                                                                                   \
    {"--size", WS_ARG_INT, (dest), 0,                                                                       \
     "working resolution, pixels a side (square images; CLIP's input is 224) [224]"}
#define WS_ROW_CUTOFF(dest) \
    {"--cutoff", WS_ARG_CUTOFF, (dest), 0, "splat cut-off radius in sigmas, or inf for the exact sum [4]"}
#define WS_ROW_THREADS(dest) {"--threads", WS_ARG_INT, (dest), 0, "threads, 0 = one per core [0]"}
#define WS_ROW_SPLIT(dest) {"--split", WS_ARG_STRING, (dest), 0, "the views: train, val or test [test]"}
#define WS_ROW_VIEW(dest) {"--view", WS_ARG_INT, (dest), 0, "view index within the split [0]"}
#define WS_ROW_CURVES(dest) {"--curves", WS_ARG_STRING, (dest), 0, "the sketch, a curve file [required]"}
#define WS_ROW_GT_CURVES(dest) \
    {"--gt-curves", WS_ARG_STRING, (dest), 0, "ground-truth curves [SCENE/gt_curves.json]"}
#define WS_ROW_IMAGES(dest) \
    {"--images", WS_ARG_STRING, (dest), 0, "a COLMAP scene's images folder [SCENE/images]"}
#define WS_ROW_MASKS(dest)                                                                     \
    {"--masks", WS_ARG_STRING, (dest), 0,                                                      \
     "folder of the views' masks (DIR/<image name> as .png; white = object) [SCENE/masks, nerfstudio and COLMAP]"}
#define WS_ROW_BBOX(dest)                                                                      \
    {"--bbox", WS_ARG_STRING, (dest), 0,                                                       \
     "the box the object is in; the line targets keep the edges the views agree on inside it " \
     "[from the scene where the views have no usable silhouette]"}
#define WS_ROW_EDGE_MAPS(dest)                                                                       \
    {"--edge-maps", WS_ARG_STRING, (dest), 0,                                                        \
     "directory of the views' edge maps (DIR/<file_path>.png) for the edges loss [none]"}
#define WS_ROW_BACKGROUND(dest)                                                                       \
    {"--background", WS_ARG_STRING, (dest), 0,                                                        \
     "photo background: black, white, auto (the image border's median) or R,G,B in [0, 1] [black]"}

/* The loss. --loss lists its choices; eval's also takes none (no loss,
 * the distances alone), WS_ROW_LOSS_OR_NONE. */
#define WS_CLI_LOSS_HELP(others) \
    "auto, " others " [auto: " WS_CLI_LOSS_AUTO " when the CLIP weight file exists, else edges]"
#define WS_ROW_LOSS(dest) {"--loss", WS_ARG_STRING, (dest), 0, WS_CLI_LOSS_HELP("clip, edges, clip+edges, sobel or l2")}
#define WS_ROW_LOSS_OR_NONE(dest) \
    {"--loss", WS_ARG_STRING, (dest), 0, WS_CLI_LOSS_HELP("clip, edges, clip+edges, sobel, l2 or none")}
#define WS_ROW_WEIGHTS(dest) \
    {"--weights", WS_ARG_STRING, (dest), 0, "CLIP weight file [weights/clip-vit-b32.bin]"}
#define WS_ROW_EDGES_WEIGHT(dest) {"--edges-weight", WS_ARG_DOUBLE, (dest), 0, "weight of the edge loss [1]"}
#define WS_ROW_CONV_WEIGHT(dest) \
    {"--clip-conv-loss", WS_ARG_DOUBLE, (dest), 0, "CLIP's geometric term weight, 0 = off [1]"}
#define WS_ROW_FC_WEIGHT(dest) {"--clip-fc-loss-weight", WS_ARG_DOUBLE, (dest), 0, "CLIP's fc term weight [0.1]"}
#define WS_ROW_LAYER_WEIGHTS(dest)                                      \
    {"--clip-conv-layer-weights", WS_ARG_DOUBLES, (dest), WS_LOSS_MAX_LAYERS, \
     "weight of CLIP's block 0, 1, ... in the geometric term [0 0 1 1 0]"}
#define WS_ROW_GEOMETRIC(dest)                                                                          \
    {"--clip-geometric", WS_ARG_STRING, (dest), 0,                                                      \
     "what CLIP's geometric term compares: blocks (outputs h_l) or attention (probabilities P_l) [blocks]"}
#define WS_ROW_HIDDEN(dest)                                                                                   \
    {"--hidden-lines", WS_ARG_STRING, (dest), 0,                                                              \
     "hidden-line removal of the stroke images: hull (drawn only where the visual hull does not hide them) " \
     "or none [hull with --loss edges, none otherwise]"}
#define WS_ROW_PRECISION(dest)                                                                              \
    {"--precision", WS_ARG_STRING, (dest), 0,                                                               \
     "CLIP's weight GEMMs: fp32, bf16 (CPUs with AVX512_BF16; gradient error below the augmentations' "    \
     "own noise, docs/RESULTS.md) or auto (bf16 where the CPU has it) [auto]"}

#endif
