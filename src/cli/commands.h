/* commands.h: the commands of the wiresketch program, one file each. Each
 * takes the arguments after its name and returns the process exit code. */
#ifndef WS_COMMANDS_H
#define WS_COMMANDS_H
#include "nn/base/status.h"

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} ws_command;

extern const ws_command ws_commands[];
extern const int ws_ncommands;

/* "exit status:" and one line per code, for `wiresketch --help`, fit's
 * --help and the man page (tools/make_man.sh reads them from there). */
extern const char ws_exit_status_text[];

int cmd_render(int argc, char **argv);
int cmd_grad(int argc, char **argv);
int cmd_export(int argc, char **argv);
int cmd_scene(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_embed(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_check(int argc, char **argv);
int cmd_sweep(int argc, char **argv);
int cmd_rank(int argc, char **argv);

/* A new fit's arguments checked as `fit` would, nothing run (cmd_fit.c). */
int cmd_fit_check_arguments(int argc, char **argv, ws_status *st);

#endif
