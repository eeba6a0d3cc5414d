/* test_sweep.c: `wiresketch sweep` on the committed fixture scene: one fit
 * per combination (a 2 x 2 grid), each with its values (the curve count
 * reaches curves.json), the contact sheet's size and cells (photo row,
 * then each run's renders, pixel for pixel), the page's rows, resuming
 * (finished runs skipped; a run without sweep.done continues from its
 * checkpoint and ends the same), and the usage errors. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "io/image.h"
#include "render/curves.h"

static char cwd[1024];
static const char *bin, *tmp;
static char out[1 << 16];

#define SWEEP "%s sweep tests/fixtures/scene_small --out %s/sw --vary n_curves=3,5 --vary thickness=0.02,0.03 " \
              "--loss edges --size 48 --max-steps 2 --quiet --threads 1 --sheet-cell 32"

static int count_in(const char *path, const char *text) {
    static char buf[1 << 20];
    int k = 0;
    for (const char *p = read_text(path, buf, sizeof buf); (p = strstr(p, text)); p++) k++;
    return k;
}

/* The contact sheet at --sheet-cell 32: a row is its name's strip (the
 * font at scale 1: 7 px and 2 px above and below), 32 px of images and
 * 4 px of gap. */
#define LABEL 11
#define PITCH (LABEL + 36)

/* The rightmost column with ink in row `row`'s name strip, or -1. */
static int label_end(const ws_image *sheet, int row) {
    int end = -1;
    for (int i = 0; i < LABEL; i++)
        for (int j = 0; j < sheet->width; j++)
            if (sheet->data[(size_t)(4 + row * PITCH + i) * sheet->width + j] < 0.5f && j > end) end = j;
    return end;
}

/* The contact sheet's cell (row, col) is the image at path, resampled. */
static int cell_is(const ws_image *sheet, int row, int col, const char *path) {
    const float white[3] = {1, 1, 1};
    ws_image img;
    ws_status st;
    if (ws_image_read(path, 32, 32, white, &img, &st)) return 0;
    int same = 1;
    size_t plane = (size_t)sheet->width * sheet->height;
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < 32; i++)
            for (int j = 0; j < 32; j++) {
                size_t at = (size_t)(4 + row * PITCH + LABEL + i) * sheet->width + 4 + col * 36 + j;
                float want = img.data[((size_t)c * 32 + i) * 32 + j];
                same &= (int)(sheet->data[c * plane + at] * 255 + 0.5f) == (int)(want * 255 + 0.5f);
            }
    ws_image_free(&img);
    return same;
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("sweep");
    if (!getcwd(cwd, sizeof cwd)) cwd[0] = '\0';
    int rc = run_cmd(out, sizeof out, SWEEP, bin, tmp);
    CHECK(rc == 0 && strstr(out, "sweep: run 4 of 4 (n_curves=5,thickness=0.03)"), "sweep: %s", out);
    const char *runs[4] = {"n_curves=3,thickness=0.02", "n_curves=3,thickness=0.03", "n_curves=5,thickness=0.02",
                           "n_curves=5,thickness=0.03"};
    char path[600], other[600];
    for (int k = 0; k < 4; k++) {
        snprintf(path, sizeof path, "%s/sw/%s/curves.json", tmp, runs[k]);
        ws_curves c;
        ws_status st;
        int ok = ws_curves_load(path, &c, &st) == WS_OK;
        CHECK(ok && c.n == (k < 2 ? 3 : 5) && c.thickness == (k % 2 ? 0.03 : 0.02), "%s: %d curves, thickness %g",
              runs[k], ok ? c.n : -1, ok ? c.thickness : -1);
        if (ok) ws_curves_free(&c);
        snprintf(path, sizeof path, "%s/sw/%s/sweep.done", tmp, runs[k]);
        CHECK(access(path, F_OK) == 0, "%s finished", runs[k]);
    }
    /* the contact sheet: 4 test views (the fixture's) x (photos + 4 runs) */
    ws_image sheet;
    ws_status st;
    const float black[3] = {0, 0, 0};
    snprintf(path, sizeof path, "%s/sw/contact_sheet.png", tmp);
    if (ws_image_read(path, 0, 0, black, &sheet, &st) == WS_OK) {
        /* as wide as the longest name, 25 characters of 6 px and a gap each side */
        CHECK(sheet.width == 8 + 25 * 6 && sheet.height == 4 + 5 * PITCH, "sheet %d x %d", sheet.width, sheet.height);
        /* each row named: "photos", then each run's name, ending where its
         * last character does (6 px each from x = 4) */
        CHECK(label_end(&sheet, 0) >= 4 + 6 * 5 && label_end(&sheet, 0) <= 4 + 6 * 6 - 2, "row 0's name ends at %d",
              label_end(&sheet, 0));
        for (int k = 0; k < 4; k++)
            CHECK(label_end(&sheet, k + 1) >= 4 + 6 * 24 && label_end(&sheet, k + 1) <= 4 + 6 * 25 - 2,
                  "row %d's name ends at %d", k + 1, label_end(&sheet, k + 1));
        snprintf(other, sizeof other, "%s/sw/%s/test/r_2_photo.png", tmp, runs[0]);
        CHECK(cell_is(&sheet, 0, 2, other), "row 0 shows the photos");
        snprintf(other, sizeof other, "%s/sw/%s/test/r_3.png", tmp, runs[2]);
        CHECK(cell_is(&sheet, 3, 3, other), "row 3 shows run 3's renders");
        ws_image_free(&sheet);
    } else {
        CHECK(0, "contact sheet: %s", st.msg);
    }
    snprintf(path, sizeof path, "%s/sw/index.html", tmp);
    CHECK(count_in(path, "/report.html\">n_curves=") == 4 && count_in(path, "<tr>") == 5 &&
              count_in(path, "/test/r_0.png\"") == 4,
          "index.html: one row per run with its renders");
    /* again: everything skipped, the same curves */
    snprintf(other, sizeof other, "%s/before.json", tmp);
    snprintf(path, sizeof path, "%s/sw/%s/curves.json", tmp, runs[1]);
    run_cmd(out, sizeof out, "cp '%s' '%s'", path, other);
    rc = run_cmd(out, sizeof out, SWEEP, bin, tmp);
    CHECK(rc == 0 && strstr(out, "run 4 of 4 (n_curves=5,thickness=0.03): done before, skipped"), "rerun: %s", out);
    /* a run without sweep.done continues from its checkpoint */
    run_cmd(out, sizeof out, "rm %s/sw/%s/sweep.done", tmp, runs[1]);
    rc = run_cmd(out, sizeof out, SWEEP, bin, tmp);
    CHECK(rc == 0 && strstr(out, "run 2 of 4 (n_curves=3,thickness=0.03): resumed"), "resume: %s", out);
    CHECK(same_file(path, other), "the resumed run ends with the same curves");
    /* a value may hold any byte but '/' and control characters: a curve
     * file "a#1.json" (relative to the working directory) makes the run
     * "init=a#1.json", whose links must reach it, not "init=a" with a
     * fragment */
    run_cmd(out, sizeof out, "mkdir -p %s/hash && cp '%s' '%s/hash/a#1.json'", tmp, path, tmp);
    rc = run_cmd(out, sizeof out,
                 "exe=$(realpath %s) && cd %s/hash && $exe sweep %s/tests/fixtures/scene_small --out sw "
                 "--vary 'init=a#1.json' --loss edges --size 48 --max-steps 1 --quiet --threads 1 --sheet-cell 32",
                 bin, tmp, cwd);
    snprintf(other, sizeof other, "%s/hash/sw/index.html", tmp);
    CHECK(rc == 0 && count_in(other, "<a href=\"init%3Da%231.json/report.html\">init=a#1.json</a>") == 1 &&
              count_in(other, "src=\"init%3Da%231.json/test/r_0.png\"") == 1,
          "index.html links a run named with '#': %s", out);
    /* usage errors */
    rc = run_cmd(out, sizeof out, "%s sweep tests/fixtures/scene_small --out %s/e --vary n_curves", bin, tmp);
    CHECK(rc == 2 && strstr(out, "wiresketch: --vary: 'n_curves' is not NAME=V1,V2,...\n"), "bad --vary: %s", out);
    rc = run_cmd(out, sizeof out, "%s sweep tests/fixtures/scene_small --out %s/late --vary out=a,b --loss edges", bin,
                 tmp);
    CHECK(rc == 2 && !strcmp(out, "wiresketch: --vary out: the sweep sets every run's --out (DIR/NAME=V,...)\n"),
          "--vary out: %s", out);
    rc = run_cmd(out, sizeof out, "%s sweep tests/fixtures/scene_small --vary n_curves=2", bin);
    CHECK(rc == 2 && strstr(out, "wiresketch: --out: required (see --help)\n"), "no --out: %s", out);
    rc = run_cmd(out, sizeof out, "%s sweep tests/fixtures/scene_small --out %s/e --vary bogus=1 --loss edges", bin, tmp);
    CHECK(rc == 2 && !strcmp(out, "wiresketch: sweep: run 1 of 1 (bogus=1): --bogus: unknown option (see --help)\n"),
          "unknown option: %s", out);
    /* every run's arguments are checked before the first fit starts */
    rc = run_cmd(out, sizeof out, "%s sweep tests/fixtures/scene_small --out %s/late --vary n_curves=3,abc --loss edges",
                 bin, tmp);
    CHECK(rc == 2 && !strcmp(out, "wiresketch: sweep: run 2 of 2 (n_curves=abc): --n-curves: 'abc' is not an integer or 'auto'\n"),
          "bad value in the last run: %s", out);
    snprintf(path, sizeof path, "%s/late", tmp);
    CHECK(access(path, F_OK) != 0, "no run started when a later run's value is bad");
    rc = run_cmd(out, sizeof out, "%s sweep --help", bin);
    CHECK(rc == 0 && !strncmp(out, "usage: wiresketch sweep SCENE --out DIR --vary", 46), "--help: %s", out);
    return check_summary();
}
