/* test_run_record.c: a fit records itself and runs again from its record;
 * its --out is protected; --loss auto says what it chose; --version and
 * `help CMD`. Short edge-loss fits of the committed fixture, one thread. */
#include <cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"

static const char *bin, *tmp;

static const char *text_of(const cJSON *o, const char *key) {
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(x) ? x->valuestring : "";
}

#define FIT "%s fit tests/fixtures/scene_small --size 64 --max-steps 20 --threads 1 --weights %s/none.bin"

static void test_record(void) {
    static char out[1 << 16], text[1 << 16], a[1 << 16], b[1 << 16];
    /* --loss auto without weights: the line loss, said in the first line */
    int rc = run_cmd(out, sizeof out, FIT " --out %s/a", bin, tmp, tmp);
    CHECK(rc == 0, "fit: %s", out);
    char expect[1024];
    snprintf(expect, sizeof expect,
             "wiresketch: --loss auto: edges (no CLIP weight file at %s/none.bin; weights/README.md says how to "
             "make one for CLIP)\n", tmp);
    CHECK(!strncmp(out, expect, strlen(expect)), "first line: %s", out);
    /* config.json: version, commit, command line, every setting */
    char path[512], version[256];
    snprintf(path, sizeof path, "%s/a/config.json", tmp);
    cJSON *j = cJSON_Parse(read_text(path, text, sizeof text));
    CHECK(j != NULL, "config.json is JSON: %s", text);
    run_cmd(version, sizeof version, "%s --version", bin);
    if (j) {
        char line[512];
        snprintf(line, sizeof line, "wiresketch %s (commit %s)\n", text_of(j, "version"), text_of(j, "commit"));
        CHECK(!strcmp(version, line) && text_of(j, "commit")[0], "--version '%s', the record's '%s'", version, line);
        const cJSON *cmd = cJSON_GetObjectItem(j, "command_line"), *s = cJSON_GetObjectItem(j, "settings");
        CHECK(cJSON_GetArraySize(cmd) == 13 && !strcmp(cJSON_GetArrayItem(cmd, 1)->valuestring, "fit") &&
                  !strcmp(cJSON_GetArrayItem(cmd, 11)->valuestring, "--out"),
              "the command line as given");
        CHECK(!strcmp(text_of(s, "loss"), "edges") && !strcmp(text_of(s, "epochs"), "auto") &&
                  !strcmp(text_of(s, "learning-rate"), "0.0003") && !strcmp(text_of(s, "max-steps"), "20"),
              "settings in effect: the loss auto chose and its defaults");
        CHECK(cJSON_IsFalse(cJSON_GetObjectItem(s, "quiet")) &&
                  cJSON_GetArraySize(cJSON_GetObjectItem(s, "clip-conv-layer-weights")) == 5 &&
                  !cJSON_GetObjectItem(s, "resume") && !cJSON_GetObjectItem(s, "overwrite") &&
                  cJSON_GetArraySize(s) >= 37,
              "a flag as a boolean, a list as an array, %d settings", cJSON_GetArraySize(s));
        cJSON_Delete(j);
    }
    /* the same --out again: refused, the folder named */
    rc = run_cmd(out, sizeof out, FIT " --out %s/a", bin, tmp, tmp);
    snprintf(expect, sizeof expect,
             "wiresketch: %s/a: holds another run's outputs (checkpoint.bin); choose another --out, replace them "
             "with --overwrite, or continue that run with `wiresketch fit --resume %s/a`\n", tmp, tmp);
    CHECK(rc == 2 && !strcmp(out, expect), "a second fit into the same --out: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, FIT " --out %s/a --overwrite --quiet", bin, tmp, tmp);
    CHECK(rc == 0, "--overwrite: %s", out);
    /* --config: the same fit again, bit for bit, in another folder */
    rc = run_cmd(out, sizeof out, "%s fit --config %s/a/config.json --out %s/b --quiet", bin, tmp, tmp);
    CHECK(rc == 0 && !strstr(out, "--loss auto"), "fit --config: %s", out);
    snprintf(path, sizeof path, "%s/a/curves.json", tmp);
    read_text(path, a, sizeof a);
    snprintf(path, sizeof path, "%s/b/curves.json", tmp);
    read_text(path, b, sizeof b);
    CHECK(a[0] && !strcmp(a, b), "curves.json of the rerun differs");
    snprintf(path, sizeof path, "%s/b/config.json", tmp);
    j = cJSON_Parse(read_text(path, text, sizeof text));
    CHECK(j != NULL, "the rerun's record: %s", text);
    if (j) {
        char want[300];
        snprintf(want, sizeof want, "%s/b", tmp);
        CHECK(!strcmp(text_of(cJSON_GetObjectItem(j, "settings"), "out"), want), "the rerun records its --out");
        cJSON_Delete(j);
    }
    rc = run_cmd(out, sizeof out, "%s fit --config %s/nothing.json", bin, tmp);
    snprintf(expect, sizeof expect, "wiresketch: %s/nothing.json: cannot open the run's record\n", tmp);
    CHECK(rc == 1 && !strcmp(out, expect), "a missing record: %d %s", rc, out);
    snprintf(path, sizeof path, "%s/bad.json", tmp);
    FILE *f = fopen(path, "w");
    if (f) {
        fprintf(f, "{\"scene\": \"tests/fixtures/scene_small\", \"settings\": {\"epochs\": 3.5}}\n");
        fclose(f);
    }
    rc = run_cmd(out, sizeof out, "%s fit --config %s", bin, path);
    snprintf(expect, sizeof expect, "wiresketch: %s: settings.epochs: neither text, a boolean nor a list\n", path);
    CHECK(rc == 1 && !strcmp(out, expect), "a malformed record: %d %s", rc, out);
}

static void test_help(void) {
    static char a[1 << 14], b[1 << 14];
    int ra = run_cmd(a, sizeof a, "%s help fit", bin), rb = run_cmd(b, sizeof b, "%s fit --help", bin);
    CHECK(ra == 0 && rb == 0 && !strcmp(a, b) && strstr(a, "--config"), "help fit is fit --help");
    /* every text option's value named for what it is */
    static const char *const commands[] = {"fit", "eval", "render", "grad", "export", "embed", "check", "rank",
                                           "scene", "bench"};
    for (size_t k = 0; k < sizeof commands / sizeof commands[0]; k++) {
        ra = run_cmd(a, sizeof a, "%s help %s", bin, commands[k]);
        CHECK(ra == 0 && !strstr(a, "VALUE") && !strstr(a, " TEXT "), "help %s names its values: %s", commands[k], a);
    }
    ra = run_cmd(a, sizeof a, "%s help fit", bin);
    CHECK(strstr(a, "  --out DIR ") && strstr(a, "  --config FILE ") && strstr(a, "  --loss NAME ") &&
              strstr(a, "  --init HOW|FILE "),
          "fit --help: DIR, FILE, NAME");
    ra = run_cmd(a, sizeof a, "%s help nothing", bin);
    CHECK(ra == 2 && !strcmp(a, "wiresketch: nothing: unknown command (see wiresketch --help)\n"), "help nothing: %s", a);
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("run_record");
    test_record();
    test_help();
    return check_summary();
}
