/* test_outputs.c: what the program writes, and where (issue 27's classes
 * of data loss and of writes outside the place asked for).
 *
 * Drives the wiresketch binary ($BUILD/wiresketch) on a small synthetic
 * scene and asserts, for each class, the exact one-line answer and exit
 * code and that nothing was lost: an output that is (or lies inside) an
 * input is refused by identity, not by spelling; temporary files are never
 * opened through a planted link; the stale-file sweep removes only this
 * program's own temporaries; a character device, FIFO or /dev/stdout is
 * written through, never replaced; `scene --out` onto an older scene
 * leaves none of its files; a fit's options keep its checkpoint readable
 * by its own --resume; views with one file name in two folders write two
 * files; JSON never holds NaN or Inf. */
#include <cJSON.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "base/json_number.h"
#include "fit/adam.h"

static char scene[300], curves[400];
static const char *bin, *tmp;
static char out[1 << 16];

#define FIT "--loss edges --size 32 --max-steps 1 --quiet --threads 1"

/* Did the run print exactly "wiresketch: LINE\n" (stdout and stderr)? */
static int said(const char *fmt, ...) {
    char line[4096], want[4200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    snprintf(want, sizeof want, "wiresketch: %s\n", line);
    if (!strcmp(out, want)) return 1;
    fprintf(stderr, "  expected: %s  printed:  %s", want, out);
    return 0;
}

static int exists(const char *fmt, ...) {
    char path[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(path, sizeof path, fmt, ap);
    va_end(ap);
    struct stat sb;
    return lstat(path, &sb) == 0;
}

static mode_t kind_of(const char *path) {
    struct stat sb;
    return lstat(path, &sb) == 0 ? sb.st_mode & S_IFMT : 0;
}

/* ------------------------------------------------- 1, 2: inputs are never outputs */

static void test_inputs_never_replaced(void) {
    char before[400];
    snprintf(before, sizeof before, "%s/photo_before.png", tmp);
    sh("cp %s/rgb/test/r_0.png %s && find %s | sort > %s/files_before", scene, before, scene, tmp);
    int rc = run_cmd(out, sizeof out, "%s fit %s --out %s " FIT, bin, scene, scene);
    CHECK(rc == 2 && said("%s: is %s, which this command reads; choose another output", scene, scene),
          "fit --out SCENE: exit %d", rc);
    rc = run_cmd(out, sizeof out, "%s fit %s --out %s/rgb " FIT, bin, scene, scene);
    CHECK(rc == 2 && said("%s/rgb: lies inside %s, which this command reads; choose an output outside it", scene,
                          scene),
          "fit --out SCENE/rgb: exit %d", rc);
    /* another spelling of the same folder: through a link */
    sh("ln -s %s %s/link", scene, tmp);
    rc = run_cmd(out, sizeof out, "%s fit %s --out %s/link/rgb " FIT, bin, scene, tmp);
    CHECK(rc == 2 && said("%s/link/rgb: lies inside %s, which this command reads; choose an output outside it",
                          tmp, scene),
          "fit --out LINK/rgb: exit %d", rc);
    rc = run_cmd(out, sizeof out, "%s render %s --scene %s --out %s/rgb/test --size 32", bin, curves, scene, scene);
    CHECK(rc == 2 && said("%s/rgb/test: lies inside %s, which this command reads; choose an output outside it",
                          scene, scene),
          "render --out SCENE/rgb/test: exit %d", rc);
    rc = run_cmd(out, sizeof out, "%s render %s --scene %s --out %s/link --size 32", bin, curves, scene, tmp);
    CHECK(rc == 2 && said("%s/link: is %s, which this command reads; choose another output", tmp, scene),
          "render --out LINK-TO-SCENE: exit %d", rc);
    sh("ln -s %s/rgb %s/rgb_link", scene, tmp);
    rc = run_cmd(out, sizeof out, "%s render %s --scene %s --out %s/rgb_link --size 32", bin, curves, scene, tmp);
    CHECK(rc == 2 && said("%s/rgb_link: lies inside %s, which this command reads; choose an output outside it", tmp,
                          scene),
          "render --out LINK-TO-SCENE/rgb: exit %d", rc);
    rc = run_cmd(out, sizeof out, "%s check %s --size 32 --write-fixed %s/fixed", bin, scene, scene);
    CHECK(rc == 2 && said("%s/fixed: lies inside %s, which this command reads; choose an output outside it", scene,
                          scene),
          "check --write-fixed SCENE/fixed: exit %d", rc);
    CHECK(sh("cmp -s %s %s/rgb/test/r_0.png", before, scene), "the scene's photo changed");
    CHECK(sh("find %s | sort | cmp -s - %s/files_before", scene, tmp), "files were added to the scene");
    /* export onto its own input, by name and by a hard link */
    char c[400];
    snprintf(c, sizeof c, "%s/c.json", tmp);
    sh("cp %s %s && ln %s %s/hard.json", curves, c, c, tmp);
    rc = run_cmd(out, sizeof out, "%s export %s --obj %s", bin, c, c);
    CHECK(rc == 2 && said("%s: is %s, which this command reads; choose another output", c, c),
          "export C --obj C: exit %d", rc);
    rc = run_cmd(out, sizeof out, "%s export %s --ply %s/hard.json", bin, c, tmp);
    CHECK(rc == 2 && said("%s/hard.json: is %s, which this command reads; choose another output", tmp, c),
          "export C --ply HARDLINK: exit %d", rc);
    CHECK(sh("cmp -s %s %s", curves, c), "the curve file changed");
}

/* ------------------------------------------------- 3: no write through a link */

static void test_no_write_through_links(void) {
    char dir[400], victim[400], target[600], link[800];
    snprintf(dir, sizeof dir, "%s/exp", tmp);
    snprintf(victim, sizeof victim, "%s/victim.txt", tmp);
    snprintf(target, sizeof target, "%s/c.obj", dir);
    mkdir(dir, 0777);
    sh("printf precious > %s", victim);
    pid_t pid = fork();
    if (pid == 0) {
        /* the child knows the PID the export will have: it plants links at
         * the temporary names of that PID, the old style and the new */
        snprintf(link, sizeof link, "%s/.wiresketch.tmp.%ld.0.c.obj", dir, (long)getpid());
        if (symlink(victim, link) != 0) _exit(126);
        snprintf(link, sizeof link, "%s.tmp.%ld", target, (long)getpid());
        if (symlink(victim, link) != 0) _exit(126);
        int null = open("/dev/null", O_WRONLY);
        if (null < 0 || dup2(null, 1) < 0 || dup2(null, 2) < 0) _exit(126);
        execl(bin, bin, "export", curves, "--obj", target, (char *)NULL);
        _exit(127);
    }
    int status;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0, "export beside planted links failed");
    CHECK(sh("printf precious | cmp -s - %s", victim), "the export wrote through a planted link");
    CHECK(kind_of(target) == S_IFREG && sh("grep -q '^v ' %s", target), "no OBJ written");
    snprintf(link, sizeof link, "%s/.wiresketch.tmp.%ld.0.c.obj", dir, (long)pid);
    CHECK(kind_of(link) == S_IFLNK, "the planted link was not left alone");

    /* a link planted where a fit puts its test renders */
    char fit_out[400];
    snprintf(fit_out, sizeof fit_out, "%s/fit_link", tmp);
    sh("mkdir -p %s %s/elsewhere && ln -s %s/elsewhere %s/test", fit_out, tmp, tmp, fit_out);
    int rc = run_cmd(out, sizeof out, "%s fit %s --out %s " FIT, bin, scene, fit_out);
    CHECK(rc == 1 && said("%s/test: is a symbolic link; remove it (outputs are not written through a link here)",
                          fit_out),
          "fit with OUT/test a link: exit %d", rc);
    /* and where a scene puts its photos */
    char scene_out[400];
    snprintf(scene_out, sizeof scene_out, "%s/scene_link", tmp);
    sh("mkdir -p %s && touch %s/.wiresketch-scene && ln -s %s/elsewhere %s/rgb", scene_out, scene_out, tmp, scene_out);
    rc = run_cmd(out, sizeof out, "%s scene cube --out %s --size 16 --views-train 1 --views-val 0 --views-test 0",
                 bin, scene_out);
    CHECK(rc == 1 && said("%s/rgb: is a symbolic link; remove it (outputs are not written through a link here)",
                          scene_out),
          "scene with DIR/rgb a link: exit %d", rc);
    CHECK(sh("test -z \"$(ls -A %s/elsewhere)\"", tmp), "files were written through a planted folder link");
}

/* ------------------------------------------------- 4: only our own stale files */

static void test_stale_sweep(void) {
    char dir[400];
    snprintf(dir, sizeof dir, "%s/stale", tmp);
    mkdir(dir, 0777);
    const char *users[] = {"notes.tmp.2024", "draft.tmp.99999", "c.obj.tmp.999999999"};
    for (int k = 0; k < 3; k++) sh("echo mine > %s/%s", dir, users[k]);
    sh("touch %s/.wiresketch.tmp.999999999.0.c.obj %s/.wiresketch.tmp.%ld.0.other.obj", dir, dir, (long)getpid());
    int rc = run_cmd(out, sizeof out, "%s export %s --obj %s/c.obj", bin, curves, dir);
    CHECK(rc == 0, "export into the folder failed: %s", out);
    for (int k = 0; k < 3; k++) CHECK(exists("%s/%s", dir, users[k]), "the user's %s was removed", users[k]);
    CHECK(!exists("%s/.wiresketch.tmp.999999999.0.c.obj", dir), "a stale temporary of a dead PID stayed");
    CHECK(exists("%s/.wiresketch.tmp.%ld.0.other.obj", dir, (long)getpid()), "a live PID's temporary was removed");
}

/* ------------------------------------------------- 5: special files written through */

static void test_special_files(void) {
    char path[400], got[400];
    snprintf(path, sizeof path, "%s/null_copy", tmp);
    if (!sh("mknod %s c 1 3 2>/dev/null", path)) /* a copy of /dev/null, as root */
        snprintf(path, sizeof path, "/dev/null"); /* without root, which cannot replace it */
    int rc = run_cmd(out, sizeof out, "%s export %s --obj %s", bin, curves, path);
    CHECK(rc == 0 && kind_of(path) == S_IFCHR, "export onto a character device: exit %d, %s", rc, out);
    snprintf(path, sizeof path, "%s/fifo", tmp);
    snprintf(got, sizeof got, "%s/from_fifo", tmp);
    mkfifo(path, 0644);
    rc = run_cmd(out, sizeof out, "timeout 20 cat %s > %s & %s export %s --obj %s; code=$?; wait; exit $code", path, got,
                     bin, curves, path);
    CHECK(rc == 0 && kind_of(path) == S_IFIFO && sh("grep -q '^v ' %s", got), "export onto a FIFO: exit %d, %s",
          rc, out);
    snprintf(got, sizeof got, "%s/from_stdout", tmp);
    rc = run_cmd(out, sizeof out, "%s export %s --obj /dev/stdout > %s", bin, curves, got);
    CHECK(rc == 0 && kind_of("/dev/stdout") == S_IFLNK && sh("grep -q '^v ' %s", got),
          "export onto /dev/stdout: exit %d, %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s export %s --obj %s", bin, curves, tmp);
    CHECK(rc == 1 && said("%s: is a directory", tmp), "export onto a folder: exit %d", rc);
}

/* ------------------------------------------------- 6: one scene per folder */

static void test_scene_rewrite(void) {
    char dir[400];
    snprintf(dir, sizeof dir, "%s/rewrite", tmp);
    int rc = run_cmd(out, sizeof out, "%s scene cube --out %s --size 16 --views-train 2 --views-val 2 --views-test 1",
                     bin, dir);
    CHECK(rc == 0, "scene failed: %s", out);
    sh("echo mine > %s/notes.txt", dir);
    rc = run_cmd(out, sizeof out, "%s scene trefoil --out %s --size 16 --views-train 2 --views-val 0 --views-test 1",
                 bin, dir);
    CHECK(rc == 0, "scene over a scene failed: %s", out);
    CHECK(!exists("%s/transforms_val.json", dir) && !exists("%s/rgb/val", dir) && !exists("%s/gt_points.ply", dir),
          "the old scene's files stayed beside the new one");
    CHECK(exists("%s/transforms_train.json", dir) && exists("%s/rgb/train/r_1.png", dir), "the new scene is missing");
    CHECK(exists("%s/notes.txt", dir), "a file that is not the scene's was removed");
    /* a COLMAP capture (images/, sparse/0, split lists) rewritten as a NeRF scene, and back */
    rc = run_cmd(out, sizeof out, "%s scene cube --out %s --size 16 --views-train 2 --views-val 1 --views-test 1 "
                 "--layout colmap --jpeg", bin, dir);
    CHECK(rc == 0 && exists("%s/sparse/0/images.bin", dir) && exists("%s/images/train/r_00001.jpg", dir) &&
              !exists("%s/rgb/train/r_1.png", dir) && !exists("%s/transforms_train.json", dir),
          "a COLMAP scene over a NeRF one: exit %d, %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s scene cube --out %s --size 16 --views-train 2 --views-val 0 --views-test 1", bin,
                 dir);
    CHECK(rc == 0 && !exists("%s/sparse/0/images.bin", dir) && !exists("%s/images/train/r_00001.jpg", dir) &&
              !exists("%s/train_list.txt", dir) && exists("%s/rgb/train/r_1.png", dir),
          "a NeRF scene over a COLMAP one kept the COLMAP files: exit %d, %s", rc, out);
    CHECK(exists("%s/notes.txt", dir), "a file that is not the scene's was removed");
    snprintf(dir, sizeof dir, "%s/users_folder", tmp);
    sh("mkdir -p %s && echo mine > %s/thesis.tex", dir, dir);
    rc = run_cmd(out, sizeof out, "%s scene cube --out %s --size 16", bin, dir);
    CHECK(rc == 2 && said("%s: not empty and not a scene written by `wiresketch scene`; choose a new or empty folder",
                          dir),
          "scene into a user's folder: exit %d", rc);
    CHECK(sh("test \"$(ls -A %s)\" = thesis.tex", dir), "scene wrote into a user's folder");
}

/* ------------------------------------------------- 7: what a fit writes, its --resume reads */

static void test_fit_bounds(void) {
    int rc = run_cmd(out, sizeof out, "%s fit %s --out %s/f7 " FIT " --edges-weight 1e300", bin, scene, tmp);
    CHECK(rc == 2 && said("--edges-weight: 1e+300 is not in [0, 1e+06]"), "--edges-weight 1e300: exit %d", rc);
    rc = run_cmd(out, sizeof out, "%s fit %s --out %s/f7 " FIT " --silhouette-weight 1e300", bin, scene, tmp);
    CHECK(rc == 2 && said("--silhouette-weight: 1e+300 is not in [0, 1e+06]"), "--silhouette-weight 1e300: exit %d",
          rc);
    rc = run_cmd(out, sizeof out, "%s fit %s --out %s/f7 " FIT " --clip-conv-layer-weights 0 1e300", bin, scene, tmp);
    CHECK(rc == 2 && said("--clip-conv-layer-weights: 1e+300 is not in [0, 1e+06]"), "layer weight 1e300: exit %d",
          rc);
    rc = run_cmd(out, sizeof out,
                 "%s fit %s --out %s/f7 --loss edges --size 32 --quiet --threads 1 --n-curves 25000 "
                 "--snapshot-every 1 --epochs 1000",
                 bin, scene, tmp);
    CHECK(rc == 2 && said("--n-curves 25000: 15000 steps keeping 15001 snapshots (--snapshot-every 1) make a "
                          "checkpoint of 3.6e+10 bytes, over the 2147483648 it may hold; lower --n-curves or "
                          "--max-steps, or raise --snapshot-every"),
          "a checkpoint over the reader's limit: exit %d", rc);
    CHECK(!exists("%s/f7", tmp), "a refused fit made its output folder");
    /* at the bounds, the checkpoint is one --resume reads */
    rc = run_cmd(out, sizeof out, "%s fit %s --out %s/f7 " FIT " --edges-weight 1e6 --silhouette-weight 1e6", bin,
                 scene, tmp);
    CHECK(rc == 0, "fit at the largest weights failed: %s", out);
    rc = run_cmd(out, sizeof out, "%s fit --resume %s/f7 --max-steps 2", bin, tmp);
    CHECK(rc == 0, "its --resume failed: %s", out);
    /* a new fit into that folder from its curves, even with --overwrite: refused before it starts, not
     * while writing */
    sh("cp %s/f7/metrics.json %s/metrics_before.json", tmp, tmp);
    rc = run_cmd(out, sizeof out, "%s fit %s --out %s/f7 " FIT " --overwrite --init %s/f7/curves.json", bin, scene,
                 tmp, tmp);
    CHECK(rc == 2 && said("%s/f7/curves.json: is %s/f7/curves.json, which this command reads; choose another output",
                          tmp, tmp),
          "fit --init OUT/curves.json: exit %d", rc);
    CHECK(sh("cmp -s %s/f7/metrics.json %s/metrics_before.json", tmp, tmp), "the refused fit rewrote metrics.json");
    /* Adam refuses a state it cannot keep finite (the caller undoes it) */
    ws_adam adam;
    ws_status st;
    ws_status_clear(&st);
    double p[2] = {0, 0}, huge[2] = {1e200, 1}, small[2] = {1, -1};
    CHECK(ws_adam_init(&adam, 2, 0.1, &st) == WS_OK, "adam init");
    CHECK(ws_adam_update(&adam, p, small) == 0, "a finite update reported as overflowing");
    CHECK(ws_adam_update(&adam, p, huge) == 1, "an overflowing second moment went unreported");
    ws_adam_free(&adam);
}

/* ------------------------------------------------- 7b: one output per view */

static void test_same_base_names(void) {
    char dir[400];
    snprintf(dir, sizeof dir, "%s/same_names", tmp);
    sh("cp -r %s %s && mkdir -p %s/rgb/a %s/rgb/b && cp %s/rgb/train/r_0.png %s/rgb/a/r_0.png && "
       "cp %s/rgb/train/r_1.png %s/rgb/b/r_0.png",
       scene, dir, dir, dir, dir, dir, dir, dir);
    CHECK(sh("python3 -c \"import json; p='%s/transforms_train.json'; t=json.load(open(p)); "
             "t['frames'][0]['file_path']='./a/r_0'; t['frames'][1]['file_path']='./b/r_0'; "
             "json.dump(t, open(p, 'w'))\"",
             dir),
          "editing the transforms failed");
    int rc = run_cmd(out, sizeof out, "%s render %s --scene %s --split train --out %s/rendered --size 32", bin, curves,
                     dir, tmp);
    CHECK(rc == 0, "render failed: %s", out);
    CHECK(exists("%s/rendered/a_r_0.png", tmp) && exists("%s/rendered/b_r_0.png", tmp) &&
              exists("%s/rendered/r_2.png", tmp) && !exists("%s/rendered/r_0.png", tmp),
          "two views of one file name did not get two files");
    CHECK(!sh("cmp -s %s/rendered/a_r_0.png %s/rendered/b_r_0.png", tmp, tmp), "the two views' files are one");
}

/* ------------------------------------------------- 12: JSON holds no NaN or Inf */

static void test_json_numbers(void) {
    char path[400], text[4096];
    snprintf(path, sizeof path, "%s/numbers.json", tmp);
    FILE *f = fopen(path, "w");
    fputc('{', f);
    ws_json_number(f, "a", NAN, 9);
    fputs(", ", f);
    ws_json_number(f, "b", -INFINITY, 9);
    fputs(", ", f);
    ws_json_number(f, "c", 0.25, 9);
    fputs(", \"d\": [", f);
    int bad = ws_json_value(f, INFINITY, 17);
    fputs("]}", f);
    fclose(f);
    cJSON *j = cJSON_Parse(read_text(path, text, sizeof text));
    CHECK(j && cJSON_IsNull(cJSON_GetObjectItem(j, "a")) && cJSON_IsNull(cJSON_GetObjectItem(j, "b")) &&
              cJSON_GetObjectItem(j, "c")->valuedouble == 0.25 && bad == 1,
          "not valid JSON with nulls: %s", text);
    CHECK(strstr(text, "\"a_why\": \"the value is nan, which JSON cannot hold\"") &&
              strstr(text, "\"b_why\": \"the value is -inf, which JSON cannot hold\""),
          "no reason beside a null: %s", text);
    cJSON_Delete(j);
    /* a ground truth so large that its point spacing overflows */
    char dir[400];
    snprintf(dir, sizeof dir, "%s/huge_gt", tmp);
    sh("cp -r %s %s && printf 'ply\\nformat ascii 1.0\\nelement vertex 3\\nproperty double x\\nproperty double y\\n"
       "property double z\\nend_header\\n1e308 1e308 1e308\\n-1e308 -1e308 -1e308\\n0 0 0\\n' > %s/gt_points.ply",
       scene, dir, dir);
    int rc = run_cmd(out, sizeof out, "(%s eval %s --curves %s --size 32 --threads 1 2>/dev/null)", bin, dir, curves);
    j = cJSON_Parse(out);
    CHECK(rc == 0 && j && strstr(out, "\"spacing\": null, \"spacing_why\": \"the value is inf, which JSON cannot hold\""),
          "eval with a huge ground truth: exit %d, %s", rc, out);
    cJSON_Delete(j);
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("outputs");
    snprintf(scene, sizeof scene, "%s/scene", tmp);
    snprintf(curves, sizeof curves, "%s/gt_curves.json", scene);
    int rc = run_cmd(out, sizeof out, "%s scene cube --out %s --size 32 --views-train 3 --views-val 1 --views-test 1",
                     bin, scene);
    CHECK(rc == 0, "scene generation failed: %s", out);
    test_inputs_never_replaced();
    test_no_write_through_links();
    test_stale_sweep();
    test_special_files();
    test_scene_rewrite();
    test_fit_bounds();
    test_same_base_names();
    test_json_numbers();
    return check_summary();
}
