/* commands.c: the table of commands (see commands.h). */
#include "commands.h"

const ws_command ws_commands[] = {
};
const int ws_ncommands = sizeof ws_commands / sizeof ws_commands[0];
