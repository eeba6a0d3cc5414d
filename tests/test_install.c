/* slow test */
/* test_install.c: `make install` into a temporary prefix serves a program
 * that embeds wiresketch through pkg-config alone: tools/embed_example.c,
 * copied away from the source tree, compiles with `pkg-config --cflags
 * --libs wiresketch`, links the shared library by its soname, and runs on
 * the fixture scene, with the l2 loss and with a CLIP model (the tiny
 * fixture's). The installed headers are the public interface and nothing
 * else: exactly the files of PUBLIC_HEADERS (wiresketch.h and what it
 * includes; a change to that list is a change of the interface, made here
 * on purpose), each compiling on its own. The installed man page names
 * every command and every option that the program's --help lists. DESTDIR
 * stages under another root with the prefix unchanged in wiresketch.pc;
 * `make uninstall` leaves no file behind. Skipped for the sanitizer build
 * (BUILD=build/san), whose objects need the sanitizer runtime at link
 * time. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"

/* Under include/wiresketch/, in C-locale order. */
#define PUBLIC_HEADERS                                                                                       \
    "base/paths.h base/progress.h " /* a scene's load reports there (scene.h) */                         \
    "base/runtime.h base/timing.h fit/fit.h fit/fit_options.h io/export.h io/image.h "                     \
    "io/pointcloud.h io/scene.h io/splits.h metrics/line_metrics.h metrics/metrics.h metrics/nearest.h "                 \
    "metrics/quality.h metrics/strays.h nn/base/rng.h nn/base/status.h objective/clip_model.h "              \
    "objective/hidden_mode.h objective/loss.h objective/objective.h render/camera.h render/curves.h "        \
    "render/lens.h " /* a view keeps its lens (scene.h) */                                               \
    "render/splat.h wiresketch.h "

static char build[256];
static const char *bin, *tmp;
static char out[1 << 16];

/* Every command of `wiresketch --help` and every option of its own --help
 * appears in the man page (options as roff writes them: \-\-name). */
static void check_man(const char *man) {
    static char commands[4096];
    run_cmd(commands, sizeof commands, "%s --help", bin);
    int ncommands = 0, noptions = 0, missing = 0;
    char *save = NULL;
    int listing = 0;
    for (char *line = strtok_r(commands, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        if (!strcmp(line, "commands:")) {
            listing = 1;
            continue;
        }
        if (strncmp(line, "  ", 2)) listing = 0; /* the next section (exit status) */
        char name[64];
        if (!listing || sscanf(line, "  %63s", name) != 1) continue;
        ncommands++;
        char heading[128];
        snprintf(heading, sizeof heading, ".SH \"WIRESKETCH %s\"", name);
        for (char *c = heading + 15; *c; c++) *c = (char)(*c >= 'a' && *c <= 'z' ? *c - 32 : *c);
        CHECK(file_has(man, heading), "man page: no section %s", heading);
        run_cmd(out, sizeof out, "%s %s --help", bin, name);
        char *save2 = NULL;
        for (char *l = strtok_r(out, "\n", &save2); l; l = strtok_r(NULL, "\n", &save2)) {
            char opt[128], roff[300];
            if (sscanf(l, "  --%127s", opt) != 1) continue;
            noptions++;
            /* roff writes every dash as \- */
            int n = snprintf(roff, sizeof roff, ".B \\-\\-");
            for (const char *c = opt; *c && n < (int)sizeof roff - 3; c++)
                n += *c == '-' ? snprintf(roff + n, sizeof roff - n, "\\-") : snprintf(roff + n, sizeof roff - n, "%c", *c);
            if (!file_has(man, roff)) {
                missing++;
                CHECK(0, "man page: %s --%s missing", name, opt);
            }
        }
    }
    CHECK(ncommands >= 9 && noptions > 60 && missing == 0, "man page: %d commands, %d options, %d missing",
          ncommands, noptions, missing);
    /* roff's e-acute is \('e; an escaped backslash before it (\e) prints "B\('ezier" */
    CHECK(file_has(man, "B\\('ezier") && !file_has(man, "\\e("), "man page: Bezier not written as B\\('ezier");
    /* fit's option groups are headings of its section */
    CHECK(file_has(man, ".SS \"input options\"") && file_has(man, ".SS \"performance options\""),
          "man page: fit's option groups are not headings");
}

int main(void) {
    const char *b = getenv("BUILD");
    snprintf(build, sizeof build, "%s", b && *b ? b : "build");
    if (strcmp(build, "build")) {
        printf("test_install: skipped for BUILD=%s (the sanitizer build)\n", build);
        return check_summary();
    }
    bin = program_path();
    tmp = test_tmpdir("install");
    /* the sub-make runs on its own: no job server of the calling make */
    const char *make = "env -u MAKEFLAGS -u MFLAGS make -s";
    int rc = run_cmd(out, sizeof out, "%s install PREFIX=%s/usr", make, tmp);
    CHECK(rc == 0, "make install: %s", out);
    char path[600];
    snprintf(path, sizeof path, "%s/usr/share/man/man1/wiresketch.1", tmp);
    check_man(path);
    /* the public headers alone, each one compiling by itself */
    rc = run_cmd(out, sizeof out, "cd %s/usr/include/wiresketch && find . -type f | sed 's|^\\./||' | LC_ALL=C sort | tr '\\n' ' '",
                 tmp);
    CHECK(rc == 0 && !strcmp(out, PUBLIC_HEADERS), "installed headers: '%s', the public ones: '%s'", out, PUBLIC_HEADERS);
    rc = run_cmd(out, sizeof out,
                 "cd %s/usr/include/wiresketch && export PKG_CONFIG_PATH=%s/usr/lib/pkgconfig && "
                 "for h in $(find . -name '*.h'); do cc -std=c11 -Wall -Wextra -Werror $(pkg-config --cflags wiresketch) "
                 "-fsyntax-only -x c $h || exit 1; done",
                 tmp, tmp);
    CHECK(rc == 0, "an installed header does not compile on its own: %s", out);
    /* the embedding example, away from the source tree, through pkg-config */
    rc = run_cmd(out, sizeof out,
                 "cp tools/embed_example.c %s/ && cd %s && export PKG_CONFIG_PATH=%s/usr/lib/pkgconfig && "
                 "cc -std=c11 embed_example.c $(pkg-config --cflags --libs wiresketch) -lm -o embed",
                 tmp, tmp, tmp);
    CHECK(rc == 0, "compile against the installed tree: %s", out);
    rc = run_cmd(out, sizeof out, "readelf -d %s/embed | grep NEEDED", tmp);
    CHECK(rc == 0 && strstr(out, "[libwiresketch.so.0]"), "linked by soname: %s", out);
    rc = run_cmd(out, sizeof out,
                 "LD_LIBRARY_PATH=%s/usr/lib %s/embed tests/fixtures/scene_small "
                 "tests/fixtures/scene_small/gt_curves.json",
                 tmp, tmp);
    CHECK(rc == 0 && strstr(out, "l2 loss"), "the installed example runs: %s", out);
    rc = run_cmd(out, sizeof out,
                 "python3 tools/convert_weights.py tests/fixtures/clip_tiny/clip_tiny_state_dict.pt %s/tiny.bin --heads 4 && "
                 "LD_LIBRARY_PATH=%s/usr/lib %s/embed tests/fixtures/scene_small "
                 "tests/fixtures/scene_small/gt_curves.json %s/tiny.bin",
                 tmp, tmp, tmp, tmp);
    CHECK(rc == 0 && strstr(out, "CLIP loss"), "the installed example runs with a CLIP model: %s", out);
    rc = run_cmd(out, sizeof out, "PKG_CONFIG_PATH=%s/usr/lib/pkgconfig pkg-config --static --libs wiresketch", tmp);
    CHECK(rc == 0 && strstr(out, "-lwiresketch") && strstr(out, "-lgif") && strstr(out, "-lopenblas") &&
              strstr(out, "-fopenmp"),
          "static link line: %s", out);
    rc = run_cmd(out, sizeof out, "%s uninstall PREFIX=%s/usr && find %s/usr -type f -o -type l | wc -l", make, tmp, tmp);
    CHECK(rc == 0 && atoi(out) == 0, "uninstall leaves %s files", out);
    /* DESTDIR: staged under another root, the prefix stays /usr/local */
    rc = run_cmd(out, sizeof out, "%s install PREFIX=/usr/local DESTDIR=%s/stage", make, tmp);
    snprintf(path, sizeof path, "%s/stage/usr/local/lib/pkgconfig/wiresketch.pc", tmp);
    CHECK(rc == 0 && file_has(path, "prefix=/usr/local\n"), "DESTDIR install: %s", out);
    snprintf(path, sizeof path, "%s/stage/usr/local/include/wiresketch/render/camera.h", tmp);
    CHECK(access(path, R_OK) == 0, "headers keep their folders");
    rc = run_cmd(out, sizeof out, "%s uninstall PREFIX=/usr/local DESTDIR=%s/stage && find %s/stage -type f | wc -l",
                 make, tmp, tmp);
    CHECK(rc == 0 && atoi(out) == 0, "DESTDIR uninstall leaves %s files", out);
    return check_summary();
}
