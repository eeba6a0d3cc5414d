/* args.h: the command-line option parser every command uses.
 *
 * A command describes its options in a table; ws_args_parse fills the
 * destinations, collects positional arguments, and fails with WS_EUSAGE on
 * an unknown option, a missing or malformed value, or a wrong number of
 * positionals. Underscores in option names are accepted for dashes
 * (--learning_rate = --learning-rate), so the original's spellings work.
 * `--help` prints the usage built from the table and sets *help. */
#ifndef WS_ARGS_H
#define WS_ARGS_H
#include "nn/base/status.h"

typedef enum {
    WS_ARG_FLAG,      /* int, set to 1 when present */
    WS_ARG_INT,       /* int */
    WS_ARG_INT_AUTO,  /* int, or "auto" for WS_ARG_AUTO: the command decides once it knows its input */
    WS_ARG_DOUBLE,    /* double, must be finite */
    WS_ARG_CUTOFF,    /* double > 0, or "inf" for INFINITY */
    WS_ARG_STRING,    /* const char * */
    WS_ARG_DOUBLES    /* ws_arg_list: 1 to count numbers that follow */
} ws_arg_kind;

#define WS_ARG_AUTO (-1) /* WS_ARG_INT_AUTO's "auto" */
#define WS_ARG_LIST_MAX 64
typedef struct {
    int n;
    double v[WS_ARG_LIST_MAX];
} ws_arg_list;

typedef struct {
    const char *name;  /* "--cutoff" */
    ws_arg_kind kind;
    void *dest;
    int count;         /* WS_ARG_DOUBLES only: at most this many (<= WS_ARG_LIST_MAX) */
    const char *help;  /* one line; the default in brackets */
} ws_arg;

/* A heading of --help and the options listed under it, for a command with
 * many: "input" over {"--config", "--resume", NULL} prints "input
 * options:" and those two rows. The rows keep the order of the command's
 * table, which the report's settings and a run's record follow. */
typedef struct {
    const char *heading;
    const char *const *names; /* NULL-terminated */
} ws_arg_group;

typedef struct {
    const char *usage;    /* "render CURVES.json --scene DIR --out DIR [options]" */
    const char *summary;  /* one line saying what the command does */
    const ws_arg *args;
    int nargs;
    int min_positional, max_positional;
    const ws_arg_group *groups; /* NULL: one list under "options:" */
    int ngroups;
} ws_command_spec;

/* Option names compare with '_' and '-' treated alike. */
int ws_arg_same_name(const char *a, const char *b);

/* On success positional[0..*npositional) point into argv. */
int ws_args_parse(const ws_command_spec *spec, int argc, char **argv, const char **positional,
                  int *npositional, int *help, ws_status *st);

/* The start of every command: clears st, the command's status, parses
 * argv by spec (ws_args_parse) and returns WS_CLI_GO_ON when the command
 * goes on, else the exit code it returns now: 0 after --help (the usage
 * printed), that of a usage error after its line on stderr (ws_cli_fail). */
#define WS_CLI_GO_ON (-1)
int ws_cli_parse(const ws_command_spec *spec, int argc, char **argv, const char **positional,
                 int *npositional, ws_status *st);

/* The value an option holds now (after parsing, or its default) as text:
 * "yes"/"no" for a flag, "%g" numbers (17 digits when 6 do not give the
 * value back), "inf", the string or "" for none, a list as "1 0.5 2". */
void ws_arg_value(const ws_arg *a, char *buf, size_t size);

/* Reports a failed command: "wiresketch: MSG" on stderr; returns the exit code. */
int ws_cli_fail(const ws_status *st);

/* Fails (WS_EIO, "standard output: write failed: REASON") when a write to
 * stdout failed: a full disk, a closed stdout, a reader that went away
 * (SIGPIPE is ignored, main.c). stdio keeps the error sticky, so one check
 * covers every printf before it; a command that prints as it goes checks
 * after each piece so that it stops early. */
int ws_cli_stdout_check(ws_status *st);

#endif
