/* slow test */
/* test_eval_consensus.c: `eval --loss edges` on a capture whose train
 * views have no usable silhouette (the cube in the box room, no masks; 224
 * px and 48 train views, the fit's working size and the capture bed's
 * views, at which the views' agreement is measured in
 * test_edge_consensus.c) scores against the line targets the fit uses, the
 * edges the views agree on in the region of interest (fit/init.h): it says
 * so in one line on stderr (and that the cube's hull is a solid's), and its test loss ranks the ground truth below
 * no curves and below the truth shifted by 5% of the object's size (eval
 * without the consensus gave all three a loss of 1). The drawing a user
 * gets of such a view (`export --svg`, as a fit's renders and report) is
 * the curves alone, with a warning: the hull carved from silhouettes that
 * hold most of the frame is the whole box, which hid 10 of the cube's 12
 * edges. A fit of it with `--n-curves auto` (the default) takes 35 curves,
 * a solid's count (fit_options.h), says so and records it in metrics.json. */
#define _XOPEN_SOURCE 700
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "metrics/metrics.h"
#include "render/curves.h"
#include "test_util.h"

static const char *bin, *tmp;

/* `eval` of curves on the room scene: its loss (NAN when it failed) and,
 * in err, what it wrote on stderr. */
static double eval_loss(const char *what, const char *curves, char *err, size_t size) {
    char out[1 << 14], errpath[400];
    snprintf(errpath, sizeof errpath, "%s/stderr.txt", tmp);
    int rc = run_cmd(out, sizeof out,
                     "%s eval %s/room --curves %s --gt '' --gt-curves '' --loss edges --size 224 2>%s", bin, tmp,
                     curves, errpath);
    read_text(errpath, err, size);
    cJSON *j = rc == 0 ? cJSON_Parse(out) : NULL;
    const cJSON *loss = cJSON_GetObjectItem(j, "loss");
    CHECK(cJSON_IsNumber(loss), "%s: exit %d: %s%s", what, rc, out, err);
    double value = cJSON_IsNumber(loss) ? loss->valuedouble : NAN;
    cJSON_Delete(j);
    printf("%s: loss %.5f\n", what, value);
    return value;
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("eval_consensus");
    char path[400], empty[400], shifted[400], err[4096];
    CHECK(sh("%s scene cube --out %s/room --background room --size 224 --views-train 48 --views-val 0 "
             "--views-test 4 >/dev/null",
             bin, tmp),
          "the room scene was not written");
    /* the reference lines would score the drawing, which no curves cannot have */
    snprintf(path, sizeof path, "%s/room/lines", tmp);
    remove_tree(path);
    snprintf(path, sizeof path, "%s/room/gt_curves.json", tmp);
    snprintf(empty, sizeof empty, "%s/empty.json", tmp);
    snprintf(shifted, sizeof shifted, "%s/shifted.json", tmp);
    ws_curves gt = {0}, none = {0};
    ws_status st;
    int rc = ws_curves_load(path, &gt, &st);
    if (!rc) {
        none.thickness = gt.thickness;
        none.overlap = gt.overlap;
        rc = ws_curves_save(empty, &none, &st);
    }
    if (!rc) {
        double lo[3], hi[3], side = 0;
        ws_curves_bbox(&gt, lo, hi);
        for (int a = 0; a < 3; a++) side = fmax(side, hi[a] - lo[a]);
        for (int k = 0; k < gt.n * 4; k++) gt.P[3 * k] += 0.05 * side;
        rc = ws_curves_save(shifted, &gt, &st);
    }
    CHECK(rc == WS_OK, "curves: %s", st.msg);
    const int gt_n = gt.n;
    ws_curves_free(&gt);
    if (rc) return check_summary();

    double truth = eval_loss("the truth", path, err, sizeof err);
    CHECK(strstr(err, "region of interest [") && strstr(err, "from where the cameras look") &&
              strstr(err, "lie on edges the train views") && strstr(err, "the lines the fit draws") &&
              strstr(err, "the photos' colours agree on") && strstr(err, "the colours' hull is a solid's"),
          "eval does not say that it scores against the edges the views agree on: %s", err);
    double nothing = eval_loss("no curves", empty, err, sizeof err);
    double moved = eval_loss("the truth shifted 5%", shifted, err, sizeof err);
    CHECK(truth < nothing, "the truth (%.5g) does not beat no curves (%.5g)", truth, nothing);
    CHECK(truth < moved, "the truth (%.5g) does not beat the 5%% shift (%.5g)", truth, moved);

    char svg[400], errpath[400];
    snprintf(svg, sizeof svg, "%s/drawing.svg", tmp);
    snprintf(errpath, sizeof errpath, "%s/stderr.txt", tmp);
    int exported = sh("%s export %s --svg %s --scene %s/room 2>%s", bin, path, svg, tmp, errpath);
    read_text(errpath, err, sizeof err);
    CHECK(exported && strstr(err, "room: 46 of the 48 train views have no usable silhouette") &&
              strstr(err, "so no hull outlines the object; the SVG is the curves alone"),
          "export --svg does not say that the drawing is the curves alone: %s", err);
    size_t size;
    char *text = slurp(svg, &size);
    int paths = 0;
    for (const char *at = text; at && (at = strstr(at, "<path")); at++) paths++;
    CHECK(paths == gt_n, "the SVG draws %d paths, not the truth's %d curves", paths, gt_n);
    free(text);

    static char out[1 << 16];
    rc = run_cmd(out, sizeof out, "%s fit %s/room --out %s/fit --loss edges --max-steps 1", bin, tmp, tmp);
    char metrics[400];
    snprintf(metrics, sizeof metrics, "%s/fit/metrics.json", tmp);
    CHECK(rc == 0 && strstr(out, "\nfit: 35 curves (--n-curves auto: 25, 35 for a solid's edges)\n") &&
              file_has(metrics, "\"curves\": 35,"),
          "a fit of the solid does not take 35 curves: exit %d: %s", rc, out);
    return check_summary();
}
