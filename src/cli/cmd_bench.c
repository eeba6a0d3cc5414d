/* cmd_bench.c: `wiresketch bench PART`: the benchmarks, one subcommand per
 * part of the program (they print tables; nothing here is a test). */
#include <stdio.h>
#include <string.h>
#include "commands.h"

int cmd_bench(int argc, char **argv) {
    static const struct {
        const char *name;
        int (*run)(int argc, char **argv);
        const char *summary;
    } parts[] = {
        {"clip", cmd_bench_clip, "CLIP forward and forward+backward against the GEMM floor"},
    };
    int nparts = (int)(sizeof parts / sizeof parts[0]);
    if (argc >= 1)
        for (int i = 0; i < nparts; i++)
            if (!strcmp(argv[0], parts[i].name)) return parts[i].run(argc - 1, argv + 1);
    int help = argc >= 1 && (!strcmp(argv[0], "--help") || !strcmp(argv[0], "-h"));
    FILE *out = help ? stdout : stderr;
    if (argc >= 1 && !help) fprintf(stderr, "wiresketch: bench %s: unknown part\n", argv[0]);
    fprintf(out, "usage: wiresketch bench PART [options]   (PART --help for details)\n\nparts:\n");
    for (int i = 0; i < nparts; i++) fprintf(out, "  %-6s %s\n", parts[i].name, parts[i].summary);
    return help ? 0 : 2;
}
