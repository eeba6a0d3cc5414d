/* commands.c: the table of commands (see commands.h). */
#include "cli/commands.h"

const ws_command ws_commands[] = {
    {"fit", cmd_fit, "fit 3D curves to a multi-view scene: the main job"},
    {"eval", cmd_eval, "test loss and distance to the ground truth of a sketch (JSON)"},
    {"render", cmd_render, "splat a sketch into every view of a split as PNGs"},
    {"grad", cmd_grad, "loss of one view and its gradient per control point (JSON)"},
    {"export", cmd_export, "write a sketch as OBJ, PLY or SVG"},
    {"embed", cmd_embed, "CLIP embedding of images, one JSON array per line"},
    {"bench", cmd_bench, "benchmarks: speed against the hardware's floor (tables)"},
    {"check", cmd_check, "check that every view's photo agrees with its camera (silhouettes)"},
    {"rank", cmd_rank, "losses of the ground truth and of worse sketches (a markdown table)"},
    {"sweep", cmd_sweep, "one fit per value of the varied options, then a contact sheet and a page"},
    {"scene", cmd_scene, "write a synthetic test scene (NeRF layout) with its ground-truth curves"},
};
const int ws_ncommands = sizeof ws_commands / sizeof ws_commands[0];

/* The exit codes (commands.h). */
const char ws_exit_status_text[] =
    "exit status:\n"
    "  0      done\n"
    "  1      bad input, or an output that could not be written (a full disk, a closed stdout, "
    "ulimit -f): one line on stderr names it, no temporary file left\n"
    "  2      bad usage\n"
    "  130    fit stopped by SIGINT (Ctrl-C): checkpoint and outputs written; `fit --resume DIR` continues\n"
    "  128+N  fit stopped by signal N, like SIGINT: 129 SIGHUP, 143 SIGTERM, 152 SIGXCPU (ulimit -t), "
    "153 SIGXFSZ (ulimit -f: what fits is written), 141 the reader of its progress gone; any other "
    "command ended by signal N, its temporary files removed\n";
