/* test_export_read.c: the exports read back by an independent reader,
 * tools/read_exports.py (Python's standard library, its own camera and
 * Bezier code): the SVG of the fixture's ground-truth curves is one path
 * of cubic segments per curve within 0.1 px of the curves' perspective
 * images (halved where one cubic does not hold them, at 1024 px), cut into
 * subpaths where the visual hull hides them with --hidden-lines hull; the
 * OBJ is one object per curve whose vertices lie on it. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"

#define FIXTURE "tests/fixtures/scene_small"
static const char *bin, *tmp;

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("export_read");
    static char out[1 << 14], svg[1 << 16];
    char path[512];
    int rc = run_cmd(out, sizeof out,
                     "%s export " FIXTURE "/gt_curves.json --svg %s/whole.svg --obj %s/curves.obj --scene " FIXTURE
                     " --size 1024 --drawing curves",
                     bin, tmp, tmp);
    CHECK(rc == 0 && !out[0], "export: %d %s", rc, out);
    rc = run_cmd(out, sizeof out,
                 "python3 tools/read_exports.py svg %s/whole.svg " FIXTURE "/gt_curves.json " FIXTURE " test 0 1024", tmp);
    int paths = 0, segments = 0;
    CHECK(rc == 0 && sscanf(out, "svg: %d paths of %d cubic segments", &paths, &segments) == 2 && paths == 12 &&
              segments > paths,
          "the SVG read back: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, "python3 tools/read_exports.py obj %s/curves.obj " FIXTURE "/gt_curves.json", tmp);
    CHECK(rc == 0 && !strcmp(out, "obj: 12 objects of 33 vertices, on their curves\n"), "the OBJ read back: %d %s",
          rc, out);
    /* hidden lines: the back of the knot is left out, curves cut */
    rc = run_cmd(out, sizeof out,
                 "%s export " FIXTURE "/gt_curves.json --svg %s/hidden.svg --scene " FIXTURE
                 " --size 64 --view 1 --hidden-lines hull --drawing curves",
                 bin, tmp);
    CHECK(rc == 0, "export --hidden-lines hull: %d %s", rc, out);
    rc = run_cmd(out, sizeof out,
                 "python3 tools/read_exports.py svg %s/hidden.svg " FIXTURE "/gt_curves.json " FIXTURE
                 " test 1 64 --hidden", tmp);
    CHECK(rc == 0 && !strncmp(out, "svg: ", 5), "the SVG without hidden lines read back: %d %s", rc, out);
    snprintf(path, sizeof path, "%s/hidden.svg", tmp);
    read_text(path, svg, sizeof svg);
    CHECK(strstr(svg, " M") != NULL, "no curve cut where the hull hides it");
    rc = run_cmd(out, sizeof out, "%s export " FIXTURE "/gt_curves.json --svg %s/x.svg --scene " FIXTURE
                 " --hidden-lines back", bin, tmp);
    CHECK(rc == 2 && !strcmp(out, "wiresketch: --hidden-lines: 'back' is not hull or none\n"), "a bad mode: %s", out);
    return check_summary();
}
