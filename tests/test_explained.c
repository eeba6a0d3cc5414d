/* test_explained.c: fit/fit_explained.h, the share of the training views'
 * lines a fit's curves explain: the ground truth's curves explain nearly
 * all of a clean cube's, curves far from the object none (NaN for a scene
 * with no line at all is not reached here), and the warning line is given
 * below the threshold only, with its exact text. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "fit/fit_explained.h"
#include "synth/synth.h"
#include "tests/check.h"
#include "tests/test_util.h"

int main(void) {
    const char *tmp = test_tmpdir("explained");
    char path[400];
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    opt.views[WS_TRAIN] = 6, opt.views[WS_VAL] = 0, opt.views[WS_TEST] = 0;
    opt.size = 96;
    ws_status st;
    ws_scene sc;
    ws_scene_options so;
    ws_scene_options_default(&so);
    so.width = so.height = 96;
    ws_view_targets *targets = NULL;
    ws_sketch_renderer r;
    ws_curves gt = {0}, far = {0};
    snprintf(path, sizeof path, "%s/gt_curves.json", tmp);
    int rc = ws_synth_write("cube", tmp, &opt, &st) || ws_scene_load(&sc, tmp, &so, &st) ||
             ws_view_targets_create(&targets, &sc, &st) || ws_sketch_renderer_init(&r, 96, 96, &st) ||
             ws_curves_load(path, &gt, &st) || ws_curves_alloc(&far, 1, &st);
    CHECK(rc == 0, "set-up: %s", st.msg);
    if (rc) return check_summary();
    double share = NAN;
    rc = ws_fit_explained(&sc, targets, &gt, &r, &share, &st);
    CHECK(rc == 0 && share > 0.9 && share <= 1, "the ground truth explains the cube's lines: %g (%s)", share,
          rc ? st.msg : "");
    char line[600];
    ws_fit_explained_line(share, 96, 96, line, sizeof line);
    CHECK(line[0] == '\0', "no warning for the ground truth: %s", line);
    /* one short curve far behind the cameras' target, out of every view */
    far.thickness = gt.thickness;
    for (int k = 0; k < 4; k++) {
        far.P[3 * k + 0] = 50 + 0.1 * k;
        far.P[3 * k + 1] = 50;
        far.P[3 * k + 2] = 50;
    }
    rc = ws_fit_explained(&sc, targets, &far, &r, &share, &st);
    CHECK(rc == 0 && share == 0, "a curve out of sight explains nothing: %g", share);
    ws_fit_explained_line(0.031, 96, 96, line, sizeof line);
    CHECK(!strcmp(line, "the curves explain 3% of the training views' lines (their line pixels within 1.4 px of a "
                        "stroke; below 20% the strokes are not where the photos' lines are, e.g. an object over a "
                        "busy background without masks: give --masks DIR or mask_path)"),
          "the warning: %s", line);
    ws_fit_explained_line(0.2, 96, 96, line, sizeof line);
    CHECK(line[0] == '\0', "20%%: no warning: %s", line);
    ws_fit_explained_line(NAN, 96, 96, line, sizeof line);
    CHECK(line[0] == '\0', "no lines at all: no warning: %s", line);
    ws_curves_free(&gt);
    ws_curves_free(&far);
    ws_sketch_renderer_free(&r);
    ws_view_targets_free(targets);
    ws_scene_free(&sc);
    return check_summary();
}
