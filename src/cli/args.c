/* args.c: the command-line option parser (see args.h). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli/args.h"

int ws_arg_same_name(const char *a, const char *b) {
    for (; *a && *b; a++, b++) {
        char ca = *a == '_' ? '-' : *a, cb = *b == '_' ? '-' : *b;
        if (ca != cb) return 0;
    }
    return *a == *b;
}

static int parse_double(const char *opt, const char *text, double *out, ws_status *st) {
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end || errno == ERANGE || !isfinite(v))
        return ws_fail(st, WS_EUSAGE, "%s: '%s' is not a finite number", opt, text);
    *out = v;
    return WS_OK;
}

/* A list ends at the next option or after `count` numbers. */
static int parse_list(const ws_arg *a, char **argv, int argc, int *i, ws_status *st) {
    ws_arg_list *list = a->dest;
    list->n = 0;
    while (*i + 1 < argc && list->n < a->count && strncmp(argv[*i + 1], "--", 2) != 0) {
        if (parse_double(a->name, argv[*i + 1], &list->v[list->n], st)) return st->code;
        list->n++;
        (*i)++;
    }
    if (list->n == 0) return ws_fail(st, WS_EUSAGE, "%s: needs 1 to %d numbers", a->name, a->count);
    return WS_OK;
}

static int parse_value(const ws_arg *a, char **argv, int argc, int *i, ws_status *st) {
    if (a->kind == WS_ARG_DOUBLES) return parse_list(a, argv, argc, i, st);
    if (*i + 1 >= argc) return ws_fail(st, WS_EUSAGE, "%s: needs a value", a->name);
    const char *text = argv[*i + 1];
    switch (a->kind) {
    case WS_ARG_INT_AUTO:
        if (!strcmp(text, "auto")) {
            *(int *)a->dest = WS_ARG_AUTO;
            break;
        }
        /* fall through */
    case WS_ARG_INT: {
        char *end;
        errno = 0;
        long v = strtol(text, &end, 10);
        if (end == text || *end || errno == ERANGE || v < -2147483647L || v > 2147483647L)
            return ws_fail(st, WS_EUSAGE, "%s: '%s' is not an integer%s", a->name, text,
                           a->kind == WS_ARG_INT_AUTO ? " or 'auto'" : "");
        *(int *)a->dest = (int)v;
        break;
    }
    case WS_ARG_DOUBLE:
        if (parse_double(a->name, text, (double *)a->dest, st)) return st->code;
        break;
    case WS_ARG_CUTOFF:
        if (!strcmp(text, "inf")) {
            *(double *)a->dest = INFINITY;
        } else {
            double v;
            if (parse_double(a->name, text, &v, st)) return st->code;
            if (!(v > 0))
                return ws_fail(st, WS_EUSAGE, "%s: '%s' must be positive or 'inf'", a->name, text);
            *(double *)a->dest = v;
        }
        break;
    case WS_ARG_STRING:
        *(const char **)a->dest = text;
        break;
    case WS_ARG_DOUBLES:
    case WS_ARG_FLAG:
        break;
    }
    (*i)++;
    return WS_OK;
}

/* What a text option's value is, in its usage line: an option means the
 * same in every command that has it. */
static const char *text_metavar(const char *name) {
    static const char *const names[][2] = {
        {"--out", "DIR"},        {"--resume", "DIR"},      {"--scene", "DIR"},        {"--edge-maps", "DIR"},
        {"--write-fixed", "DIR"}, {"--config", "FILE"},    {"--curves", "FILE"},      {"--gt", "FILE"},
        {"--gt-curves", "FILE"}, {"--obj", "FILE"},        {"--ply", "FILE"},         {"--svg", "FILE"},
        {"--weights", "FILE"},   {"--weights-f16", "FILE"}, {"--weights-f32", "FILE"}, {"--init", "HOW|FILE"},
        {"--loss", "NAME"},      {"--split", "NAME"},      {"--layout", "NAME"},      {"--clip-geometric", "MODE"},
        {"--hidden-lines", "MODE"}, {"--background", "COLOR"}, {"--images", "DIR"},      {"--masks", "DIR"},      {"--precision", "MODE"},
        {"--lens", "K1,K2,P1,P2"}, {"--size", "N|WxH"},   {"--principal", "DX,DY"}, {"--drawing", "MODE"},
        {"--bbox", "X0,Y0,Z0,X1,Y1,Z1"},
    };
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        if (!strcmp(names[k][0], name)) return names[k][1];
    return "TEXT";
}

static void print_option(const ws_arg *a) {
    const char *value = a->kind == WS_ARG_FLAG      ? ""
                        : a->kind == WS_ARG_INT     ? "N"
                        : a->kind == WS_ARG_INT_AUTO ? "N|auto"
                        : a->kind == WS_ARG_STRING  ? text_metavar(a->name)
                        : a->kind == WS_ARG_CUTOFF  ? "K|inf"
                        : a->kind == WS_ARG_DOUBLES ? "X..."
                                                    : "X";
    char head[64];
    snprintf(head, sizeof head, "%s%s%s", a->name, *value ? " " : "", value);
    printf("  %-26s  %s\n", head, a->help); /* two spaces at least: tools/make_man.sh splits there */
}

/* The group of spec that lists option a, or -1. */
static int group_of(const ws_command_spec *spec, const ws_arg *a) {
    for (int g = 0; g < spec->ngroups; g++)
        for (const char *const *n = spec->groups[g].names; *n; n++)
            if (!strcmp(*n, a->name)) return g;
    return -1;
}

/* Prints the options of group g (-1: those no group lists) under heading,
 * when there are any. */
static void print_group(const ws_command_spec *spec, int g, const char *heading) {
    int listed = 0;
    for (int k = 0; k < spec->nargs; k++) {
        if (group_of(spec, &spec->args[k]) != g) continue;
        if (!listed++) printf("\n%s:\n", heading);
        print_option(&spec->args[k]);
    }
}

/* The usage line, the summary and every option, under the headings of
 * spec's groups; an option no group lists comes last, under "other
 * options:", so that none is left out. */
static void print_usage(const ws_command_spec *spec) {
    printf("usage: wiresketch %s\n%s\n", spec->usage, spec->summary);
    for (int g = 0; g < spec->ngroups; g++) {
        char heading[64];
        snprintf(heading, sizeof heading, "%s options", spec->groups[g].heading);
        print_group(spec, g, heading);
    }
    print_group(spec, -1, spec->ngroups ? "other options" : "options");
}

int ws_args_parse(const ws_command_spec *spec, int argc, char **argv, const char **positional,
                  int *npositional, int *help, ws_status *st) {
    *npositional = 0;
    *help = 0;
    for (int i = 0; i < argc; i++) {
        const char *word = argv[i];
        if (!strcmp(word, "--help") || !strcmp(word, "-h")) {
            print_usage(spec);
            *help = 1;
            return WS_OK;
        }
        if (word[0] == '-' && word[1] == '-') {
            const ws_arg *a = NULL;
            for (int k = 0; k < spec->nargs && !a; k++)
                if (ws_arg_same_name(spec->args[k].name, word)) a = &spec->args[k];
            if (!a) return ws_fail(st, WS_EUSAGE, "%s: unknown option (see --help)", word);
            if (a->kind == WS_ARG_FLAG)
                *(int *)a->dest = 1;
            else if (parse_value(a, argv, argc, &i, st))
                return st->code;
            continue;
        }
        if (*npositional >= spec->max_positional)
            return ws_fail(st, WS_EUSAGE, "%s: unexpected argument (usage: wiresketch %s)", word,
                           spec->usage);
        positional[(*npositional)++] = word;
    }
    if (*npositional < spec->min_positional)
        return ws_fail(st, WS_EUSAGE, "missing argument (usage: wiresketch %s)", spec->usage);
    return WS_OK;
}

int ws_cli_parse(const ws_command_spec *spec, int argc, char **argv, const char **positional,
                 int *npositional, ws_status *st) {
    ws_status_clear(st);
    int help;
    if (ws_args_parse(spec, argc, argv, positional, npositional, &help, st)) return ws_cli_fail(st);
    return help ? 0 : WS_CLI_GO_ON;
}

int ws_cli_fail(const ws_status *st) {
    fprintf(stderr, "wiresketch: %s\n", st->msg);
    return ws_exit_code(st);
}

int ws_cli_stdout_check(ws_status *st) {
    errno = 0;
    /* the flush retries what is buffered and so gives the reason (errno) */
    if (fflush(stdout) == 0 && !ferror(stdout)) return WS_OK;
    int err = errno ? errno : EIO;
    return ws_fail(st, WS_EIO, "standard output: write failed: %s", strerror(err));
}

/* "%g" when it reads back as v, else "%.17g". */
static int put_number(char *buf, size_t size, double v) {
    char six[32];
    snprintf(six, sizeof six, "%g", v);
    return snprintf(buf, size, strtod(six, NULL) == v ? "%g" : "%.17g", v);
}

void ws_arg_value(const ws_arg *a, char *buf, size_t size) {
    buf[0] = '\0';
    switch (a->kind) {
    case WS_ARG_FLAG:
        snprintf(buf, size, "%s", *(const int *)a->dest ? "yes" : "no");
        break;
    case WS_ARG_INT:
        snprintf(buf, size, "%d", *(const int *)a->dest);
        break;
    case WS_ARG_INT_AUTO:
        if (*(const int *)a->dest == WS_ARG_AUTO)
            snprintf(buf, size, "auto");
        else
            snprintf(buf, size, "%d", *(const int *)a->dest);
        break;
    case WS_ARG_DOUBLE:
    case WS_ARG_CUTOFF:
        if (isinf(*(const double *)a->dest))
            snprintf(buf, size, "inf");
        else
            put_number(buf, size, *(const double *)a->dest);
        break;
    case WS_ARG_STRING: {
        const char *v = *(const char *const *)a->dest;
        snprintf(buf, size, "%s", v ? v : "");
        break;
    }
    case WS_ARG_DOUBLES: {
        const ws_arg_list *list = a->dest;
        size_t used = 0;
        for (int k = 0; k < list->n && used < size; k++) {
            if (k) used += (size_t)snprintf(buf + used, size - used, " ");
            if (used < size) used += (size_t)put_number(buf + used, size - used, list->v[k]);
        }
        break;
    }
    }
}
