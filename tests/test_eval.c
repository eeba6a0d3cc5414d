/* test_eval.c: `wiresketch eval` on the committed fixture scene: by
 * default (--loss auto) the edge loss without CLIP weights and clip+edges
 * when the weight file exists (the tiny test model), each announced in the
 * first line; the distances alone with --loss none; and the errors when a
 * loss's needs are not met or there is nothing to measure. */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"

#define FIXTURE "tests/fixtures/scene_small"
static const char *bin, *tmp;

/* --loss auto's line (stderr, before the JSON) of the last eval_json, or "". */
static char auto_line[1024];

/* Runs `eval ARGS`, expecting exit 0 and one JSON object, after --loss
 * auto's line when it chose. */
static cJSON *eval_json(const char *what, const char *args) {
    static char out[1 << 14];
    int rc = run_cmd(out, sizeof out, "%s eval %s", bin, args);
    const char *json = out, *prefix = "wiresketch: --loss auto: ";
    auto_line[0] = '\0';
    if (!strncmp(out, prefix, strlen(prefix)) && strchr(out, '\n')) {
        json = strchr(out, '\n') + 1;
        snprintf(auto_line, sizeof auto_line, "%.*s", (int)(json - out), out);
    }
    cJSON *j = rc == 0 ? cJSON_Parse(json) : NULL;
    CHECK(j != NULL, "%s: exit %d: %s", what, rc, out);
    return j;
}

static const char *kind(const cJSON *j) {
    const cJSON *k = cJSON_GetObjectItem(j, "loss_kind");
    return cJSON_IsString(k) ? k->valuestring : "";
}

static void test_eval(void) {
    char args[2048], out[4096], weights[512];
    /* no weights: the edge loss by default, and the distances to the
     * scene's own ground truth */
    snprintf(args, sizeof args, FIXTURE " --curves " FIXTURE "/gt_curves.json --weights %s/none.bin --size 64",
             tmp);
    cJSON *j = eval_json("no weights", args);
    char expect[1024];
    snprintf(expect, sizeof expect,
             "wiresketch: --loss auto: edges (no CLIP weight file at %s/none.bin; weights/README.md says how to "
             "make one for CLIP)\n", tmp);
    CHECK(!strcmp(auto_line, expect), "--loss auto's line without weights: '%s'", auto_line);
    if (j) {
        const cJSON *ch = cJSON_GetObjectItem(j, "chamfer"), *f = cJSON_GetObjectItem(j, "fscore");
        CHECK(!strcmp(kind(j), "edges") && cJSON_IsNumber(cJSON_GetObjectItem(j, "loss")),
              "the edge loss without weights");
        CHECK(cJSON_IsNumber(ch) && ch->valuedouble < 1e-6 && cJSON_IsNumber(f) && f->valuedouble == 1,
              "the truth against itself: chamfer %g", cJSON_IsNumber(ch) ? ch->valuedouble : -1);
        CHECK(cJSON_IsNumber(cJSON_GetObjectItem(j, "surface_mean")), "gt_points.ply measured");
        CHECK(cJSON_GetObjectItem(j, "views")->valueint == 4, "test views");
        cJSON_Delete(j);
    }
    /* --per-curve: where surface_mean comes from, curve by curve; the
     * fixture's first curve moved 1 away from everything adds the most */
    snprintf(args, sizeof args, "%s/moved.json", tmp);
    FILE *f = fopen(args, "w");
    if (f) {
        fprintf(f, "{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": ["
                   "[[0,0,3],[0.1,0,3],[0.2,0,3],[0.3,0,3]], [[0,0,0],[0.1,0,0],[0.2,0,0],[0.3,0,0]]]}\n");
        fclose(f);
    }
    snprintf(args, sizeof args, FIXTURE " --curves %s/moved.json --loss none --per-curve", tmp);
    j = eval_json("--per-curve", args);
    if (j) {
        const cJSON *per = cJSON_GetObjectItem(j, "surface_curves");
        double adds = 0;
        int n = 0, beyond = 0;
        for (int c = 0; c < cJSON_GetArraySize(per); c++) {
            const cJSON *pc = cJSON_GetArrayItem(per, c);
            adds += cJSON_GetObjectItem(pc, "adds")->valuedouble;
            n += cJSON_GetObjectItem(pc, "gaussians")->valueint;
            beyond += cJSON_GetObjectItem(pc, "beyond_p90")->valueint;
        }
        double mean = cJSON_GetObjectItem(j, "surface_mean")->valuedouble;
        const cJSON *far = cJSON_GetArrayItem(per, 0), *near = cJSON_GetArrayItem(per, 1);
        CHECK(cJSON_GetArraySize(per) == 2 && n == cJSON_GetObjectItem(j, "gaussians")->valueint &&
                  fabs(adds - mean) < 1e-8 * mean && beyond <= n / 10,
              "per-curve sums: %d curves, %d Gaussians, adds %g of %g, %d beyond p90", cJSON_GetArraySize(per), n,
              adds, mean, beyond);
        CHECK(far && near &&
                  cJSON_GetObjectItem(far, "mean")->valuedouble > cJSON_GetObjectItem(near, "mean")->valuedouble,
              "the moved curve is the farther");
        cJSON_Delete(j);
    }
    int prc = run_cmd(out, sizeof out, "%s eval %s/bare --curves " FIXTURE "/gt_curves.json --loss none --gt-curves "
                      FIXTURE "/gt_curves.json --per-curve", bin, tmp);
    CHECK(prc == 2 && !strcmp(out, "wiresketch: --per-curve: no ground-truth point cloud to measure against (give --gt)\n"),
          "--per-curve without a point cloud: %d %s", prc, out);
    /* --loss edges: computed, no weights needed */
    snprintf(args, sizeof args, FIXTURE " --curves " FIXTURE "/gt_curves.json --loss edges --size 64");
    j = eval_json("--loss edges", args);
    if (j) {
        const cJSON *l = cJSON_GetObjectItem(j, "loss");
        CHECK(!strcmp(kind(j), "edges") && cJSON_IsNumber(l), "edge loss computed");
        cJSON_Delete(j);
    }
    /* an explicit CLIP loss without weights: the weight file's message */
    int rc = run_cmd(out, sizeof out, "%s eval " FIXTURE " --curves " FIXTURE "/gt_curves.json --loss clip --weights %s/none.bin",
                     bin, tmp);
    CHECK(rc == 1 && strstr(out, "none.bin: no CLIP weight file") && strstr(out, "--loss edges"),
          "--loss clip without weights: %d %s", rc, out);
    /* nothing to measure: no loss and no ground truth */
    rc = run_cmd(out, sizeof out, "%s eval %s/bare --curves " FIXTURE "/gt_curves.json --loss none", bin, tmp);
    char want[1200];
    snprintf(want, sizeof want, "wiresketch: nothing to evaluate: --loss none and no ground truth (give --gt or "
             "--gt-curves; %s/bare/lines/test has no reference lines)\n", tmp);
    CHECK(rc == 2 && !strcmp(out, want), "no loss, no ground truth: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s eval --help", bin);
    CHECK(rc == 0 && strstr(out, "[auto: clip+edges when the CLIP weight file exists, else edges]"),
          "--help states the rule");
    /* weights present: CLIP by default (the tiny test model) */
    snprintf(weights, sizeof weights, "%s/tiny.bin", tmp);
    rc = run_cmd(out, sizeof out,
                 "python3 tools/convert_weights.py tests/fixtures/clip_tiny/clip_tiny_state_dict.pt %s",
                 weights);
    CHECK(rc == 0, "converting the tiny model: %s", out);
    snprintf(args, sizeof args,
             FIXTURE " --curves " FIXTURE "/gt_curves.json --weights %s --size 64 --clip-conv-layer-weights 1 1",
             weights);
    j = eval_json("weights present", args);
    snprintf(expect, sizeof expect, "wiresketch: --loss auto: clip+edges (the CLIP weight file %s exists)\n",
             weights);
    CHECK(!strcmp(auto_line, expect), "--loss auto's line with weights: '%s'", auto_line);
    if (j) {
        const cJSON *l = cJSON_GetObjectItem(j, "loss");
        CHECK(!strcmp(kind(j), "clip+edges") && cJSON_IsNumber(l), "clip+edges by default with weights");
        cJSON_Delete(j);
    }
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("eval");
    char out[512];
    /* a scene without ground truth: the fixture's cameras and images */
    run_cmd(out, sizeof out, "mkdir -p %s/bare && cp -r " FIXTURE "/transforms_*.json " FIXTURE "/rgb %s/bare",
            tmp, tmp);
    test_eval();
    return check_summary();
}
