/* test_limits.c: inputs and options that would ask for unbounded work or
 * memory are refused first, in one line naming the limit (base/limits.h):
 * curves per file, Gaussians per view (thin or many curves), the decoded
 * size of a photo (checked from its header, before its pixels), frames per
 * scene file, a sweep's contact sheet, OMP_STACKSIZE; and the hull's byte
 * counter takes any number of views. Each answer comes in seconds. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include "check.h"
#include "test_util.h"
#include "base/limits.h"
#include "geometry/hull.h"

static char out[8192];
static const char *bin, *tmp;

/* n curves, each a segment of length `length` along x, of `thickness`. */
static void write_curves(const char *path, int n, double length, double thickness) {
    FILE *f = fopen(path, "w");
    if (!f) return;
    fprintf(f, "{\"thickness\": %g, \"overlap\": 0.6, \"curves\": [", thickness);
    for (int i = 0; i < n; i++)
        fprintf(f, "%s[[0,%d,0],[%g,%d,0],[%g,%d,0],[%g,%d,0]]", i ? "," : "", i % 7, length / 3, i % 7,
                2 * length / 3, i % 7, length, i % 7);
    fputs("]}\n", f);
    fclose(f);
}

static void chunk(FILE *f, const char *type, const unsigned char *data, unsigned len) {
    unsigned char be[4] = {len >> 24, len >> 16 & 255, len >> 8 & 255, len & 255};
    fwrite(be, 1, 4, f);
    fwrite(type, 1, 4, f);
    if (len) fwrite(data, 1, len, f);
    uLong crc = crc32(crc32(0, (const Bytef *)type, 4), data, len);
    unsigned char c[4] = {crc >> 24, crc >> 16 & 255, crc >> 8 & 255, crc & 255};
    fwrite(c, 1, 4, f);
}

/* A PNG header of w x h 16-bit RGBA, interlaced, and no pixels: what a
 * decoder learns before it allocates. Interlaced, the file's samples are
 * held whole beside the float planes (a file that is not is read a row at
 * a time). */
static void write_png_header(const char *path, unsigned w, unsigned h) {
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fwrite("\x89PNG\r\n\x1a\n", 1, 8, f);
    unsigned char ihdr[13] = {w >> 24, w >> 16 & 255, w >> 8 & 255, w & 255, h >> 24, h >> 16 & 255,
                              h >> 8 & 255, h & 255, 16, 6, 0, 0, 1};
    chunk(f, "IHDR", ihdr, 13);
    unsigned char idat[16];
    uLongf n = sizeof idat;
    const unsigned char zero[2] = {0, 0};
    compress(idat, &n, zero, 2);
    chunk(f, "IDAT", idat, (unsigned)n);
    chunk(f, "IEND", NULL, 0);
    fclose(f);
}

static void test_curves(const char *scene) {
    char path[400];
    snprintf(path, sizeof path, "%s/many.json", tmp);
    write_curves(path, WS_MAX_CURVES + 1, 0.1, 0.02);
    char want[600];
    snprintf(want, sizeof want, "wiresketch: %s: %d curves, more than the %d a curve file may hold\n", path,
             WS_MAX_CURVES + 1, WS_MAX_CURVES);
    int rc = run_cmd(out, sizeof out, "%s export %s --obj %s/many.obj", bin, path, tmp);
    CHECK(rc == 1 && !strcmp(out, want), "export of %d curves: exit %d, said %s", WS_MAX_CURVES + 1, rc, out);
    rc = run_cmd(out, sizeof out, "%s eval %s --curves %s --loss edges --size 32", bin, scene, path);
    CHECK(rc == 1 && !strcmp(out, want), "eval of %d curves: exit %d, said %s", WS_MAX_CURVES + 1, rc, out);

    /* 2,000 curves of length 1 at thickness 1e-6: 4,096 Gaussians each
     * (the cap per curve), 8 million in all */
    snprintf(path, sizeof path, "%s/thin.json", tmp);
    write_curves(path, 2000, 1.0, 1e-6);
    snprintf(want, sizeof want,
             "wiresketch: curves: more than %d Gaussians, the most one view takes (2000 curves of thickness "
             "1e-06); use fewer, shorter or thicker curves\n",
             WS_MAX_GAUSSIANS);
    rc = run_cmd(out, sizeof out, "%s render %s --scene %s --out %s/thin --size 32", bin, path, scene, tmp);
    CHECK(rc == 1 && !strcmp(out, want), "render of 8 million Gaussians: exit %d, said %s", rc, out);
    /* a fit whose first curves pass it stops before its first step (it
     * skipped every step and failed at its outputs) */
    snprintf(want, sizeof want,
             "wiresketch: curves: more than %d Gaussians, the most one view takes (2000 curves of thickness "
             "1e-09); use fewer, shorter or thicker curves\n",
             WS_MAX_GAUSSIANS);
    rc = run_cmd(out, sizeof out, "%s fit %s --out %s/thin_fit --size 32 --loss edges --n-curves 2000 --thickness "
                 "1e-9 --length 0.3 --max-steps 1 --threads 1 --quiet", bin, scene, tmp);
    snprintf(path, sizeof path, "%s/thin_fit/checkpoint.bin", tmp);
    CHECK(rc == 1 && !strcmp(out, want) && access(path, F_OK) != 0, "a fit of 8 million Gaussians: exit %d, said %s",
          rc, out);
}

static void test_png(void) {
    char png[400], want[1200];
    snprintf(png, sizeof png, "%s/huge.png", tmp);
    write_png_header(png, 8192, 8192);
    snprintf(want, sizeof want,
             "wiresketch: %s (8192 x 8192 pixels, 4 channels of 16 bits, decoded): 196608 x 8192 = 1610612736 "
             "bytes, more than the 1073741824 a decoded image may take\n",
             png);
    int rc = run_cmd(out, sizeof out, "%s embed --weights tests/fuzz/corpus/weights/tiny_f32.bin %s", bin, png);
    CHECK(rc == 1 && !strcmp(out, want), "an 8192 x 8192 16-bit PNG: exit %d, said %s", rc, out);
}

static void test_frames(void) {
    char dir[300], path[400], want[600];
    snprintf(dir, sizeof dir, "%s/frames", tmp);
    mkdir(dir, 0777);
    snprintf(path, sizeof path, "%s/transforms.json", dir);
    FILE *f = fopen(path, "w");
    if (!f) return;
    fputs("{\"fl_x\": 50, \"fl_y\": 50, \"cx\": 32, \"cy\": 32, \"w\": 64, \"h\": 64, \"frames\": [", f);
    for (int i = 0; i <= WS_MAX_VIEWS; i++)
        fprintf(f, "%s{\"file_path\": \"images/%d.png\", \"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,4],"
                   "[0,0,0,1]]}", i ? "," : "", i);
    fputs("]}\n", f);
    fclose(f);
    snprintf(want, sizeof want, "wiresketch: %s: %d frames, more than the %d a scene file may have\n", path,
             WS_MAX_VIEWS + 1, WS_MAX_VIEWS);
    int rc = run_cmd(out, sizeof out, "%s check %s", bin, dir);
    CHECK(rc == 1 && !strcmp(out, want), "%d frames: exit %d, said %s", WS_MAX_VIEWS + 1, rc, out);
}

static void test_sheet(const char *scene) {
    char want[600];
    snprintf(want, sizeof want,
             "wiresketch: sweep: the contact sheet of 3 runs with --sheet-views 1024 --sheet-cell 1024: 1052676 x "
             "4188 x 3 x 4 = 52903285056 bytes, more than the 2147483648 a contact sheet may take\n");
    int rc = run_cmd(out, sizeof out, "%s sweep %s --out %s/sweep --vary seed=1,2,3 --sheet-cell 1024 "
                     "--sheet-views 1024 --loss edges", bin, scene, tmp);
    CHECK(rc == 2 && !strcmp(out, want), "a 52 GB contact sheet: exit %d, said %s", rc, out);
    struct stat sb;
    snprintf(want, sizeof want, "%s/sweep", tmp);
    CHECK(stat(want, &sb) != 0, "the refused sweep made its folder");
}

/* OMP_STACKSIZE outside what threads can be made with: libgomp's first
 * thread creation failed with its own line (exit 1) in the middle of the
 * run; now the program's line, before anything runs. */
static void test_stack_size(const char *scene) {
    static const char *const values[][2] = {{"16k", "out of range"}, {"100G", "out of range"}};
    for (int k = 0; k < 2; k++) {
        char want[300];
        snprintf(want, sizeof want, "wiresketch: OMP_STACKSIZE=%s: %s; each thread needs from 128K to 256M (unset "
                 "it: the default is enough)\n", values[k][0], values[k][1]);
        int rc = run_cmd(out, sizeof out, "OMP_STACKSIZE=%s %s eval %s --curves %s/gt_curves.json --loss edges "
                         "--threads 2", values[k][0], bin, scene, scene);
        CHECK(rc == 2 && !strcmp(out, want), "OMP_STACKSIZE=%s: exit %d, said %s", values[k][0], rc, out);
    }
    int rc = run_cmd(out, sizeof out, "OMP_STACKSIZE=4M %s eval %s --curves %s/gt_curves.json --loss edges "
                     "--threads 2 >/dev/null", bin, scene, scene);
    CHECK(rc == 0, "OMP_STACKSIZE=4M: exit %d, said %s", rc, out);
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("limits");
    char scene[300];
    snprintf(scene, sizeof scene, "%s/scene", tmp);
    int rc = run_cmd(out, sizeof out, "%s scene trefoil --out %s --size 32 --views-train 3 --views-val 1 "
                     "--views-test 1", bin, scene);
    CHECK(rc == 0, "scene: %s", out);
    /* 5,020 views made tolerance 251 and the hull refused it ("hull: 5020
     * views, resolution 64, tolerance 251", naming no file) */
    CHECK(ws_hull_default_tolerance(5020) == 250 && ws_hull_default_tolerance(100) == 5,
          "default hull tolerance %d of 5020 views", ws_hull_default_tolerance(5020));
    test_curves(scene);
    test_png();
    test_frames();
    test_sheet(scene);
    test_stack_size(scene);
    return check_summary();
}
