/* test_cli_help.c: the commands' --help texts. An option that several
 * commands take reads the same in each (src/cli/cli_rows.h), and `fit
 * --help` lists every option once, under its group's heading. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_util.h"


#define NCOMMANDS 8
static const char *const commands[NCOMMANDS] = {"fit", "eval", "render", "grad", "export", "check", "rank", "bench"};
static char help[NCOMMANDS][1 << 15];

/* The line of `help` that lists option `name` ("--size"), or NULL; *count
 * gets how many lines list it. */
static const char *option_line(const char *help_text, const char *name, char *line, size_t size, int *count) {
    const char *found = NULL;
    *count = 0;
    size_t n = strlen(name);
    for (const char *p = help_text; *p;) {
        const char *end = strchr(p, '\n');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (len > n + 2 && !strncmp(p, "  ", 2) && !strncmp(p + 2, name, n) && (p[2 + n] == ' ')) {
            if (!found++) snprintf(line, size, "%.*s", (int)len, p);
            (*count)++;
        }
        p += len + (end != NULL);
    }
    return found ? line : NULL;
}

/* Every command that takes one of these shared options lists the same line
 * for it: the same help text and placeholder. */
static void test_shared_rows(void) {
    static const char *const shared[] = {
        "--size",         "--threads",      "--cutoff",         "--split",   "--view",
        "--curves",       "--gt-curves",    "--images",         "--edge-maps", "--background",
        "--loss",         "--edges-weight", "--clip-conv-loss", "--clip-fc-loss-weight",
        "--clip-conv-layer-weights",        "--clip-geometric", "--precision",
    };
    for (size_t k = 0; k < sizeof shared / sizeof shared[0]; k++) {
        char first[1024] = "", line[1024];
        int commands_with = 0, same = 1;
        for (int c = 0; c < NCOMMANDS; c++) {
            int count;
            /* eval's --loss also takes none (WS_ROW_LOSS_OR_NONE) */
            if (!strcmp(shared[k], "--loss") && !strcmp(commands[c], "eval")) continue;
            if (!option_line(help[c], shared[k], line, sizeof line, &count)) continue;
            CHECK(count == 1, "%s --help lists %s %d times", commands[c], shared[k], count);
            if (!commands_with++) snprintf(first, sizeof first, "%s", line);
            if (strcmp(first, line)) {
                same = 0;
                CHECK(0, "%s --help: '%s', another command: '%s'", commands[c], line, first);
            }
        }
        CHECK(commands_with >= 2 && same, "%s: in %d commands, %s", shared[k], commands_with,
              same ? "one text" : "different texts");
    }
}

/* fit's options stand under the headings of their groups, each once,
 * none left over under "other options:". */
static void test_fit_groups(void) {
    static const char *const headings[] = {"\ninput options:\n",    "\nloss options:\n",
                                           "\ncurve options:\n",    "\nschedule options:\n",
                                           "\noutput options:\n",   "\nperformance options:\n"};
    const char *fit = help[0], *last = fit;
    for (size_t k = 0; k < sizeof headings / sizeof headings[0]; k++) {
        const char *at = strstr(fit, headings[k]);
        CHECK(at && at > last, "fit --help: heading '%.*s' missing or out of order", (int)strlen(headings[k]) - 2,
              headings[k] + 1);
        if (at) last = at;
    }
    CHECK(!strstr(fit, "other options:") && !strstr(fit, "\noptions:\n"), "fit --help: an option outside the groups");
    static const char *const some[] = {"--resume", "--loss", "--n-curves", "--epochs", "--out", "--threads", "--init",
                                       "--quiet"};
    for (size_t k = 0; k < sizeof some / sizeof some[0]; k++) {
        char line[1024];
        int count;
        option_line(fit, some[k], line, sizeof line, &count);
        CHECK(count == 1, "fit --help lists %s %d times", some[k], count);
    }
    /* --resume's value is the run's output directory */
    char line[1024];
    int count;
    CHECK(option_line(fit, "--resume", line, sizeof line, &count) && !strncmp(line, "  --resume DIR ", 15),
          "fit --help: %s", line);
}

int main(void) {
    for (int c = 0; c < NCOMMANDS; c++) {
        int rc = run_cmd(help[c], sizeof help[c], "%s %s --help", program_path(), commands[c]);
        CHECK(rc == 0 && !strncmp(help[c], "usage: wiresketch ", 18), "%s --help: %d %s", commands[c], rc, help[c]);
    }
    test_shared_rows();
    test_fit_groups();
    return check_summary();
}
