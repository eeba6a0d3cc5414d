/* test_gt_coverage.c: the ground-truth coverage check (geometry/
 * gt_coverage.h) on the fixture scene: its complete ground truth covers
 * the silhouettes; a copy whose gt_points.ply lacks the points within 0.3
 * of one point (a piece of the knot) is flagged, near that piece, by
 * `check` (which still exits 0: the ground truth does not enter a fit) and
 * by `eval` (a warning and gt_coverage.flagged). */
#include <cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/paths.h"
#include "check.h"
#include "test_util.h"
#include "geometry/check.h"
#include "geometry/gt_coverage.h"
#include "objective/view_targets.h"
#include "render/curves.h"
#include "scene_load.h"

#define FIXTURE "tests/fixtures/scene_small"
#define CUT_RADIUS 0.3

static const char *bin, *tmp;

/* The coverage of `dir`'s gt_points.ply at the check's default size. */
static int measure(const char *dir, ws_gt_coverage *c) {
    ws_status st;
    ws_scene scene = {0};
    ws_view_targets *targets = NULL;
    ws_pointcloud pc = {0};
    ws_curves tubes = {0};
    const ws_silhouette *sil[WS_NSPLITS];
    char points[WS_PATH_MAX], curves[WS_PATH_MAX];
    snprintf(points, sizeof points, "%s/gt_points.ply", dir);
    snprintf(curves, sizeof curves, "%s/gt_curves.json", dir);
    int rc = load_scene_at(&scene, dir, 224, &st) || ws_view_targets_create(&targets, &scene, &st) ||
             ws_pointcloud_load_ply(points, &pc, &st) || ws_curves_load(curves, &tubes, &st);
    for (int s = 0; s < WS_NSPLITS && !rc; s++) rc = ws_view_targets_silhouettes(targets, s, &sil[s], &st);
    if (!rc) rc = ws_gt_coverage_measure(&scene, sil, &pc, tubes.thickness, points, WS_CHECK_RESOLUTION, c, &st);
    CHECK(rc == WS_OK, "%s: %s", dir, st.msg);
    ws_curves_free(&tubes);
    ws_pointcloud_free(&pc);
    ws_view_targets_free(targets);
    ws_scene_free(&scene);
    return rc;
}

/* tmp/cut: the fixture with the gt_points.ply points within CUT_RADIUS of
 * its first point left out; removed: their centroid. */
static int cut_copy(const char *dir, double removed[3]) {
    ws_status st;
    ws_pointcloud pc = {0};
    if (ws_pointcloud_load_ply(FIXTURE "/gt_points.ply", &pc, &st)) {
        CHECK(0, "fixture points: %s", st.msg);
        return 1;
    }
    char path[WS_PATH_MAX], out[1024];
    run_cmd(out, sizeof out, "mkdir -p %s && for f in rgb transforms_train.json transforms_val.json transforms_test.json "
        "gt_curves.json; do ln -s \"$PWD/" FIXTURE "/$f\" %s/$f; done", dir, dir);
    const double *o = pc.xyz;
    int kept = 0, n = 0;
    for (int i = 0; i < pc.n; i++) {
        const double *p = &pc.xyz[3 * i];
        kept += hypot(hypot(p[0] - o[0], p[1] - o[1]), p[2] - o[2]) > CUT_RADIUS;
    }
    snprintf(path, sizeof path, "%s/gt_points.ply", dir);
    FILE *f = fopen(path, "wb");
    if (f) fprintf(f, "ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
                      "property double z\nend_header\n", kept);
    removed[0] = removed[1] = removed[2] = 0;
    for (int i = 0; i < pc.n && f; i++) {
        const double *p = &pc.xyz[3 * i];
        if (hypot(hypot(p[0] - o[0], p[1] - o[1]), p[2] - o[2]) > CUT_RADIUS) {
            fprintf(f, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
            continue;
        }
        for (int a = 0; a < 3; a++) removed[a] += p[a];
        n++;
    }
    for (int a = 0; a < 3; a++) removed[a] /= n;
    int rc = !f || fclose(f) != 0;
    CHECK(!rc && n > 0 && kept > 0, "the cut copy: %d points left out, %d kept", n, kept);
    ws_pointcloud_free(&pc);
    return rc;
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("gt_coverage");
    char out[1 << 16], cut[400], want[2 * WS_GT_LINE];
    ws_gt_coverage c;
    /* complete: below both thresholds, no line */
    if (measure(FIXTURE, &c) == WS_OK)
        CHECK(!c.flagged && c.line[0] == 0 && c.region_voxels < WS_GT_REGION_VOXELS &&
                  c.split[WS_TRAIN].mean < WS_GT_UNCOVERED_FLAG,
              "the complete ground truth passes: %.4f uncovered, %ld voxels", c.split[WS_TRAIN].mean,
              c.region_voxels);
    int rc = run_cmd(out, sizeof out, "%s check " FIXTURE " 2>&1", bin);
    CHECK(rc == 0 && strstr(out, FIXTURE "/gt_points.ply: the ground truth covers the silhouettes\n") &&
              !strstr(out, "warning"),
          "check of the fixture: exit %d: %s", rc, out);
    /* a piece of the knot left out */
    snprintf(cut, sizeof cut, "%s/cut", tmp);
    double removed[3];
    if (cut_copy(cut, removed) || measure(cut, &c)) return check_summary();
    double off = hypot(hypot(c.centroid[0] - removed[0], c.centroid[1] - removed[1]), c.centroid[2] - removed[2]);
    CHECK(c.flagged && c.split[WS_TRAIN].mean >= WS_GT_UNCOVERED_FLAG && c.region_voxels >= WS_GT_REGION_VOXELS &&
              off < 0.15,
          "the cut is flagged near the removed piece: %.4f uncovered, %ld voxels around (%g, %g, %g), %g from "
          "(%g, %g, %g)", c.split[WS_TRAIN].mean, c.region_voxels, c.centroid[0], c.centroid[1], c.centroid[2],
          off, removed[0], removed[1], removed[2]);
    snprintf(want, sizeof want,
             "%s/gt_points.ply: the ground truth misses part of the object every photo shows: about %.1f%% of the "
             "silhouettes, around (%.2f, %.2f, %.2f) (extent ", cut, 100 * c.split[WS_TRAIN].mean, c.centroid[0],
             c.centroid[1], c.centroid[2]);
    CHECK(!strncmp(c.line, want, strlen(want)) &&
              !strcmp(c.line + strlen(c.line) - strlen("); surface distances there measure the ground truth, not "
                                                       "the sketch"),
                      "); surface distances there measure the ground truth, not the sketch"),
          "the line: %s", c.line);
    rc = run_cmd(out, sizeof out, "%s check %s 2>/dev/null", bin, cut);
    snprintf(want, sizeof want, "\n%s\n", c.line);
    CHECK(rc == 0 && strstr(out, want), "check of the cut copy: exit 0 (a fit is not refused), the line: %d %s", rc,
          out);
    /* on a terminal (stdout and stderr the same), the line once */
    rc = run_cmd(out, sizeof out, "python3 -c 'import pty, sys; pty.spawn(sys.argv[1:])' %s check %s", bin, cut);
    int times = 0;
    for (const char *at = strstr(out, c.line); at; at = strstr(at + 1, c.line)) times++;
    CHECK(times == 1, "check on a terminal shows the line %d times: %s", times, out);
    rc = run_cmd(out, sizeof out, "%s check %s 2>&1 >/dev/null", bin, cut);
    snprintf(want, sizeof want, "wiresketch: warning: %s\n", c.line);
    CHECK(rc == 0 && !strcmp(out, want), "check's warning on stderr: %s", out);
    rc = run_cmd(out, sizeof out, "%s eval %s --curves " FIXTURE "/gt_curves.json --loss none 2>&1 >/dev/null", bin, cut);
    CHECK(rc == 0 && !strcmp(out, want), "eval's warning on stderr: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s eval %s --curves " FIXTURE "/gt_curves.json --loss none 2>/dev/null", bin, cut);
    cJSON *j = rc == 0 ? cJSON_Parse(out) : NULL;
    const cJSON *g = cJSON_GetObjectItem(j, "gt_coverage"), *u = cJSON_GetObjectItem(g, "train_uncovered");
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(g, "flagged")) && cJSON_IsNumber(u) &&
              fabs(u->valuedouble - c.split[WS_TRAIN].mean) < 1e-8 &&
              cJSON_GetArraySize(cJSON_GetObjectItem(g, "region_centroid")) == 3,
          "eval's gt_coverage: %s", out);
    cJSON_Delete(j);
    /* a fit says it too: metrics.json's gt_coverage with the line, the
     * report's warning above its metrics; a fit of the complete fixture
     * has neither flag nor warning */
    static char text[1 << 20];
    const char *dirs[2] = {cut, FIXTURE};
    for (int k = 0; k < 2; k++) {
        rc = run_cmd(out, sizeof out, "%s fit %s --out %s/fit%d --loss edges --max-steps 5 --threads 1 --quiet 2>&1",
                 bin, dirs[k], tmp, k);
        CHECK(rc == 0, "fit of %s: %s", dirs[k], out);
        char path[600];
        snprintf(path, sizeof path, "%s/fit%d/metrics.json", tmp, k);
        FILE *f = fopen(path, "rb");
        size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
        if (f) fclose(f);
        text[n] = '\0';
        j = cJSON_Parse(text);
        g = cJSON_GetObjectItem(j, "gt_coverage");
        const cJSON *w = cJSON_GetObjectItem(g, "warning");
        CHECK(k == 0 ? cJSON_IsTrue(cJSON_GetObjectItem(g, "flagged")) && cJSON_IsString(w) &&
                           !strcmp(w->valuestring, c.line)
                     : cJSON_IsFalse(cJSON_GetObjectItem(g, "flagged")) && !w,
              "metrics.json's gt_coverage of %s: %s", dirs[k], text);
        cJSON_Delete(j);
        snprintf(path, sizeof path, "%s/fit%d/report.html", tmp, k);
        f = fopen(path, "rb");
        n = f ? fread(text, 1, sizeof text - 1, f) : 0;
        if (f) fclose(f);
        text[n] = '\0';
        snprintf(want, sizeof want, "<p class=\"warning\" id=\"gt-warning\">Warning: %s. The distances", c.line);
        CHECK(k == 0 ? strstr(text, want) != NULL : !strstr(text, "gt-warning"), "the report's warning of %s", dirs[k]);
    }
    /* without a photo the sketch is still measured (the cameras are all a
     * measure needs), with a warning in place of the coverage */
    char bare[400]; /* the cut copy's files copied, not linked, one photo removed */
    snprintf(bare, sizeof bare, "%s/bare", tmp);
    run_cmd(out, sizeof out, "cp -rL %s %s && rm %s/rgb/train/r_0.png", cut, bare, bare);
    rc = run_cmd(out, sizeof out, "%s eval %s --curves " FIXTURE "/gt_curves.json --loss none 2>&1 >/dev/null", bin, bare);
    snprintf(want, sizeof want,
             "wiresketch: warning: %s/transforms_train.json: frame 0: image not found (tried %s/train/r_0.png, "
             "%s/rgb/train/r_0.png); the ground truth's coverage of the photos is not measured\n",
             bare, bare, bare);
    CHECK(rc == 0 && !strcmp(out, want), "eval without a photo: exit %d, stderr %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s eval %s --curves " FIXTURE "/gt_curves.json --loss none 2>/dev/null", bin, bare);
    j = rc == 0 ? cJSON_Parse(out) : NULL;
    CHECK(cJSON_IsNumber(cJSON_GetObjectItem(j, "surface_mean")) && !cJSON_GetObjectItem(j, "gt_coverage"),
          "eval without a photo measures the sketch and leaves gt_coverage out: %s", out);
    cJSON_Delete(j);
    return check_summary();
}
