/* slow test */
/* test_bad_input.c: the table "Bad input and faults" of docs/USAGE.md, asserted.
 *
 * Drives the wiresketch binary ($BUILD/wiresketch) through every class of
 * bad input: truncated files, wrong magic, wrong shapes, NaN and Inf values,
 * sizes that would overflow a computation, paths that do not exist, a
 * read-only output directory, a full disk and bad usage. For each it
 * asserts the exact answer: stderr is exactly one line "wiresketch: PATH:
 * problem", the exit code is 1 for bad input and 2 for bad usage, no
 * temporary file is left and no result file is created; when a fit fails
 * while writing, its last checkpoint still loads. The broken files are made
 * here from a synthetic scene, a short fit's checkpoint and the tiny weight
 * file of the fuzz corpus. */
#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>
#include "check.h"
#include "test_util.h"
#include "fit/checkpoint.h"

static const char *tmp;

static int write_all(const char *path, const void *data, size_t len) {
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    int ok = fwrite(data, 1, len, f) == len;
    return fclose(f) == 0 && ok;
}

static int write_text(const char *path, const char *text) { return write_all(path, text, strlen(text)); }

/* stderr of the last run is exactly "wiresketch: MSG\n" (printf-style). */
static int stderr_is(const char *fmt, ...) {
    char want[4096];
    int n = snprintf(want, sizeof want, "wiresketch: ");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(want + n, sizeof want - n, fmt, ap);
    va_end(ap);
    strncat(want, "\n", sizeof want - strlen(want) - 1);
    const char *got = run_stderr();
    int same = !strcmp(got, want);
    if (!same) fprintf(stderr, "stderr was: %s", got);
    return same;
}

/* Expands to: exit code, then the exact stderr line (after "wiresketch: "). */
#define ANSWER(code, rc, ...) ((rc) == (code) && stderr_is(__VA_ARGS__))

static const char *const results[] = {"curves.json", "curves.obj", "curves.ply", "log.csv",
                                       "metrics.json", "report.html", "turntable.gif",
                                       "evolution.gif"};

/* No temporary file anywhere under dir and no result file in it. */
static int no_partial_outputs(const char *dir) {
    if (!sh("test -z \"$(find %s -name '*.tmp.*' 2>/dev/null)\"", dir)) return 0;
    for (size_t i = 0; i < sizeof results / sizeof results[0]; i++) {
        char path[600];
        snprintf(path, sizeof path, "%s/%s", dir, results[i]);
        if (access(path, F_OK) == 0) return 0;
    }
    return 1;
}

static int checkpoint_loads(const char *path) {
    ws_fit_state s;
    ws_status st = {0};
    int argc;
    char **argv;
    if (ws_checkpoint_load(path, &s, &argc, &argv, &st)) {
        fprintf(stderr, "%s\n", st.msg);
        return 0;
    }
    ws_fit_state_free(&s);
    ws_checkpoint_free_args(argc, argv);
    return 1;
}

/* ------------------------------------------------------ binary file edits */

static void put_u32(unsigned char *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (unsigned char)(v >> (8 * i));
}
static void put_u64(unsigned char *p, uint64_t v) {
    for (int i = 0; i < 8; i++) p[i] = (unsigned char)(v >> (8 * i));
}
static uint32_t get_u32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Stores the right crc32 in the last 4 bytes, so that the loader looks
 * past the checksum at the edit. */
static void fix_crc(unsigned char *data, size_t len) {
    put_u32(data + len - 4, (uint32_t)crc32(0L, data, (uInt)(len - 4)));
}

/* Writes base with `edit` applied at `at` (n bytes) and the crc fixed. */
static int write_edited(const char *path, const unsigned char *base, size_t len, size_t at,
                        const void *edit, size_t n) {
    unsigned char *copy = malloc(len);
    if (!copy) return 0;
    memcpy(copy, base, len);
    memcpy(copy + at, edit, n);
    fix_crc(copy, len);
    int ok = write_all(path, copy, len);
    free(copy);
    return ok;
}

/* ------------------------------------------------------------ the classes */

#define FIT "--loss edges --size 32 --threads 1 --quiet --max-steps 2"

/* tmp/NAME: a copy of the synthetic scene. */
static const char *scene_copy(const char *name) {
    static char dir[300];
    snprintf(dir, sizeof dir, "%s/%s", tmp, name);
    sh("rm -rf %s && cp -r %s/scene %s", dir, tmp, dir);
    return dir;
}

static void test_scenes(void) {
    char out[300], path[400];
    snprintf(out, sizeof out, "%s/out_scene", tmp);
    /* a scene directory that does not exist */
    int rc = run("fit %s/nowhere --out %s " FIT, tmp, out);
    CHECK(ANSWER(1, rc, "%s/nowhere: cannot open scene directory: No such file or directory", tmp),
          "missing scene");
    CHECK(access(out, F_OK) != 0, "a failed fit created its output directory");
    /* a transforms file cut short */
    const char *s = scene_copy("s_truncated");
    snprintf(path, sizeof path, "%s/transforms_train.json", s);
    write_text(path, "{\n  \"camera_angle_x\": 0.7,\n  \"frames\": [{\"file_path\": \"train/r_0\",\n");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: JSON syntax error near line 3", path), "truncated transforms");
    /* a frame whose matrix has the wrong shape, one with an Inf entry */
    s = scene_copy("s_shape");
    snprintf(path, sizeof path, "%s/transforms_train.json", s);
    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"train/r_0\", "
                     "\"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]}, "
                     "{\"file_path\": \"train/r_1\", \"transform_matrix\": [[1, 0, 0], [0, 1, 0], "
                     "[0, 0, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: frame 1: transform_matrix is not 4x4", path), "3x3 matrix");
    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"train/r_0\", "
                     "\"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1e999], "
                     "[0, 0, 0, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: frame 0: transform_matrix has a non-finite entry", path), "Inf matrix");
    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"train/r_0\", "
                     "\"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1e300], "
                     "[0, 0, 0, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: frame 0: camera too far out (its distance to the scene centre overflows)",
                 path),
          "camera at 1e300");
    /* degenerate cameras: a field of view of 1e-300, a rotation scaled by
     * 1e100, a bottom row that is not 0 0 0 1 */
    write_text(path, "{\"camera_angle_x\": 1e-300, \"frames\": [{\"file_path\": \"train/r_0\", "
                     "\"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: camera_angle_x 1e-300 is not in [0.001, pi - 0.001]", path), "tiny angle");
    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"train/r_0\", "
                     "\"transform_matrix\": [[1e100, 0, 0, 0], [0, 1e100, 0, 0], [0, 0, 1e100, 4], "
                     "[0, 0, 0, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: frame 0: transform_matrix's rotation is not orthonormal (R^T R differs "
                        "from I by 1e+200)", path),
          "rotation scaled by 1e100");
    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"train/r_0\", "
                     "\"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 1, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: frame 0: transform_matrix's bottom row is not 0 0 0 1", path), "bottom row");
    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"../scene/train/r_0\", "
                     "\"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: frame 0: file_path '../scene/train/r_0' leaves the scene directory ('..')",
                 path),
          "file_path out of the scene");
    write_text(path, "{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"train/r_9\", "
                     "\"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]}]}");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: frame 0: image not found (tried %s/train/r_9.png, %s/rgb/train/r_9.png)",
                 path, s, s),
          "missing image");
    CHECK(no_partial_outputs(out) && access(out, F_OK) != 0, "outputs after a bad scene");
}

/* Paths that are not regular files: a FIFO would block the open (or the
 * read) forever, /dev/zero never ends, a directory cannot be read. Each is
 * refused by type before anything reads it; a regular file over its cap by
 * size. */
static void test_special_files(void) {
    char out[300], fifo[400], path[400], image[400];
    snprintf(out, sizeof out, "%s/out_special", tmp);
    snprintf(fifo, sizeof fifo, "%s/fifo", tmp);
    snprintf(image, sizeof image, "%s/scene/rgb/train/r_0.png", tmp);
    CHECK(sh("mkfifo %s", fifo), "mkfifo failed");
    int rc = run("embed --weights %s %s", fifo, image);
    CHECK(ANSWER(1, rc, "%s: not a regular file", fifo), "FIFO as --weights");
    rc = run("fit %s/scene --out %s --init %s " FIT, tmp, out, fifo);
    CHECK(ANSWER(1, rc, "%s: not a regular file", fifo), "FIFO as --init");
    rc = run("fit %s/scene --out %s --init %s " FIT, tmp, out, tmp);
    CHECK(ANSWER(1, rc, "%s: not a regular file", tmp), "directory as --init");
    const char *s = scene_copy("s_fifo_png");
    snprintf(path, sizeof path, "%s/rgb/train/r_1.png", s);
    CHECK(sh("rm %s && mkfifo %s", path, path), "mkfifo failed");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: not a regular file", path), "FIFO as an image");
    s = scene_copy("s_fifo_json");
    snprintf(path, sizeof path, "%s/transforms_val.json", s);
    CHECK(sh("rm %s && mkfifo %s", path, path), "mkfifo failed");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: not a regular file", path), "FIFO as transforms");
    CHECK(sh("rm %s && ln -s /dev/zero %s", path, path), "symlink failed");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: not a regular file", path), "/dev/zero as transforms");
    CHECK(sh("rm %s && truncate -s 65M %s", path, path), "truncate failed");
    rc = run("fit %s --out %s " FIT, s, out);
    CHECK(ANSWER(1, rc, "%s: larger than 67108864 bytes", path), "huge transforms");
    snprintf(path, sizeof path, "%s/w_huge.bin", tmp); /* sparse: no disk used */
    CHECK(sh("truncate -s 5G %s", path), "truncate failed");
    rc = run("embed --weights %s %s", path, image);
    CHECK(ANSWER(1, rc, "%s: larger than 4294967296 bytes", path), "5 GB weight file");
    unlink(path);
    CHECK(no_partial_outputs(out), "outputs after a special file");
}

/* The PNG of view 1 replaced by `data`. */
static const char *broken_png(const char *name, const void *data, size_t len) {
    static char path[400];
    const char *s = scene_copy(name);
    snprintf(path, sizeof path, "%s/rgb/train/r_1.png", s);
    write_all(path, data, len);
    return path;
}

static void test_pngs(void) {
    char out[300], good[400];
    snprintf(out, sizeof out, "%s/out_png", tmp);
    snprintf(good, sizeof good, "%s/scene/rgb/train/r_0.png", tmp);
    size_t len;
    unsigned char *png = (unsigned char *)slurp(good, &len);
    CHECK(png && len > 60, "no PNG to break");
    if (!png || len <= 60) return;
    const char *path = broken_png("s_png_cut", png, 50);
    int rc = run("fit %s/s_png_cut --out %s " FIT, tmp, out);
    CHECK(ANSWER(1, rc, "%s: truncated or corrupt PNG (unexpected end of file)", path), "cut PNG");
    path = broken_png("s_png_magic", "GIF89a\1\0\1\0", 10);
    rc = run("fit %s/s_png_magic --out %s " FIT, tmp, out);
    CHECK(ANSWER(1, rc, "%s: a GIF image, not PNG or JPEG (convert it to JPEG or PNG)", path), "GIF as PNG");
    /* IHDR claiming 100000 x 100000 pixels (40 GB of samples), crc right */
    unsigned char *big = malloc(len);
    memcpy(big, png, len);
    const unsigned char side[4] = {0x00, 0x01, 0x86, 0xa0};
    memcpy(big + 16, side, 4);
    memcpy(big + 20, side, 4);
    uint32_t crc = (uint32_t)crc32(0L, big + 12, 17);
    for (int i = 0; i < 4; i++) big[29 + i] = (unsigned char)(crc >> (24 - 8 * i));
    path = broken_png("s_png_huge", big, len);
    rc = run("fit %s/s_png_huge --out %s " FIT, tmp, out);
    CHECK(ANSWER(1, rc, "%s: image too large (100000 x 100000 pixels)", path), "huge PNG");
    free(big);
    free(png);
    CHECK(no_partial_outputs(out) && access(out, F_OK) != 0, "outputs after a bad PNG");
}

/* Offsets in the tiny weight file (weights/README.md): entry i of the
 * table at 40 + 120 i; its shape at +72, its data offset at +104. */
enum { WF_ENTRY0 = 40, WF_ENTRY = 120, WF_CONV1 = 0, WF_PROJ = 19 };

static void test_weights(void) {
    const char *tiny = "tests/fuzz/corpus/weights/tiny_f32.bin";
    char path[400], image[400];
    snprintf(image, sizeof image, "%s/scene/rgb/train/r_0.png", tmp);
    size_t len;
    unsigned char *w = (unsigned char *)slurp(tiny, &len);
    CHECK(w && len > 3000, "%s missing", tiny);
    if (!w || len <= 3000) return;
    CHECK(run("embed --weights %s %s", tiny, image) == 0, "the tiny weight file does not load");
    /* missing: fit says how to make one */
    snprintf(path, sizeof path, "%s/none.bin", tmp);
    char out[300];
    snprintf(out, sizeof out, "%s/out_weights", tmp);
    int rc = run("fit %s/scene --out %s --loss clip --size 32 --max-steps 2 --weights %s", tmp, out, path);
    CHECK(ANSWER(1, rc,
                 "%s: no CLIP weight file; convert OpenAI's ViT-B-32.pt once with `python3 "
                 "tools/convert_weights.py ViT-B-32.pt %s` (see weights/README.md), or run without "
                 "CLIP: --loss edges",
                 path, path),
          "missing weights");
    CHECK(access(out, F_OK) != 0, "a fit without weights created its output directory");
    /* truncated: below the header, and in the middle of the data */
    snprintf(path, sizeof path, "%s/w_cut.bin", tmp);
    write_all(path, w, 30);
    rc = run("embed --weights %s %s", path, image);
    CHECK(ANSWER(1, rc, "%s: truncated (30 bytes; a weight file has at least 44)", path), "cut header");
    unsigned char *half = malloc(len / 2);
    memcpy(half, w, len / 2);
    fix_crc(half, len / 2);
    write_all(path, half, len / 2);
    free(half);
    rc = run("embed --weights %s %s", path, image);
    CHECK(ANSWER(1, rc, "%s: tensor positional_embedding lies outside the file (bytes 4096 + 160, "
                        "data ends at 4190; truncated?)", path),
          "cut data");
    /* wrong magic */
    snprintf(path, sizeof path, "%s/w_magic.bin", tmp);
    write_edited(path, w, len, 0, "PK\3\4", 4);
    rc = run("embed --weights %s %s", path, image);
    CHECK(ANSWER(1, rc, "%s: not a wiresketch weight file (bad magic); convert weights with "
                        "tools/convert_weights.py", path),
          "bad magic");
    /* damaged: one bit flipped, checksum left as it was */
    w[len - 100] ^= 1;
    write_all(path, w, len);
    unsigned computed = (unsigned)crc32(0L, w, (uInt)(len - 4));
    w[len - 100] ^= 1;
    rc = run("embed --weights %s %s", path, image);
    CHECK(ANSWER(1, rc, "%s: checksum mismatch (stored %08x, computed %08x): the file is corrupt", path,
                 get_u32(w + len - 4), computed),
          "flipped bit");
    /* wrong shape: proj [8, 4] stored as [4, 8] (same size) */
    unsigned char shape[16];
    put_u64(shape, 4);
    put_u64(shape + 8, 8);
    snprintf(path, sizeof path, "%s/w_shape.bin", tmp);
    write_edited(path, w, len, WF_ENTRY0 + WF_ENTRY * WF_PROJ + 72, shape, 16);
    rc = run("embed --weights %s %s", path, image);
    CHECK(ANSWER(1, rc, "%s: tensor proj has shape [4, 8], expected [8, 4]", path), "proj shape");
    /* a shape whose size overflows 64 bits */
    put_u64(shape, (uint64_t)1 << 40);
    put_u64(shape + 8, (uint64_t)1 << 40);
    snprintf(path, sizeof path, "%s/w_huge.bin", tmp);
    write_edited(path, w, len, WF_ENTRY0 + WF_ENTRY * WF_PROJ + 72, shape, 16);
    rc = run("embed --weights %s %s", path, image);
    CHECK(ANSWER(1, rc, "%s: tensor proj has shape [1099511627776, 1099511627776], larger than the file",
                 path),
          "huge shape");
    /* NaN and Inf values in conv1.weight */
    size_t data = (size_t)w[WF_ENTRY0 + 104] | (size_t)w[WF_ENTRY0 + 105] << 8;
    const float bad[2] = {NAN, -INFINITY};
    for (int k = 0; k < 2; k++) {
        snprintf(path, sizeof path, "%s/w_%s.bin", tmp, k ? "inf" : "nan");
        write_edited(path, w, len, data + 4 * (size_t)(5 + k), &bad[k], 4);
        rc = run("embed --weights %s %s", path, image);
        CHECK(ANSWER(1, rc, "%s: tensor conv1.weight has a non-finite value at index %d", path, 5 + k),
              "non-finite weight %d", k);
    }
    free(w);
}

static void test_curve_files(void) {
    char out[300], path[400];
    snprintf(out, sizeof out, "%s/out_curves", tmp);
    snprintf(path, sizeof path, "%s/c.json", tmp);
    const struct {
        const char *text, *message;
    } cases[] = {
        {"{\"thickness\": 0.02, \"overlap\": 0.6,\n \"curves\": [[[0, 0, 0], [1, 0, 0],\n",
         "JSON syntax error near line 2"},
        {"{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]}",
         "curve 0 is not 4 points"},
        {"{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": [[[0, 0, 0], [1, 0, 0], [0, 1, 0], "
         "[0, 0, 1]], [[0, 0, 0], [1, 0, 0], [0, 1], [0, 0, 1]]]}",
         "curve 1: point 2 is not 3 numbers"},
        {"{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": [[[0, 0, 0], [1e999, 0, 0], [0, 1, 0], "
         "[0, 0, 1]]]}",
         "curve 0: point 1 is not finite"},
        {"{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": [[[0, 0, 0], [NaN, 0, 0], [0, 1, 0], "
         "[0, 0, 1]]]}",
         "JSON syntax error near line 1"},
        {"{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": [[[0, 0, 0], [1e300, 0, 0], "
         "[0, 1e300, 0], [0, 0, 1e300]]]}",
         "curve 0 is too long to measure"},
        {"{\"thickness\": -1, \"overlap\": 0.6, \"curves\": []}", "thickness -1 is not positive"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        write_text(path, cases[k].text);
        int rc = run("fit %s/scene --out %s --init %s " FIT, tmp, out, path);
        CHECK(ANSWER(1, rc, "%s: %s", path, cases[k].message), "curve file %zu", k);
    }
    /* render and eval read curve files through the same loader */
    write_text(path, cases[5].text);
    int rc = run("render %s --scene %s/scene --out %s/render_long --size 32", path, tmp, tmp);
    CHECK(ANSWER(1, rc, "%s: %s", path, cases[5].message), "render: curve too long");
    rc = run("eval %s/scene --curves %s --loss edges --size 32", tmp, path);
    CHECK(ANSWER(1, rc, "%s: %s", path, cases[5].message), "eval: curve too long");
    snprintf(path, sizeof path, "%s/no_such_curves.json", tmp);
    rc = run("fit %s/scene --out %s --init %s " FIT, tmp, out, path);
    CHECK(ANSWER(1, rc, "%s: cannot open: No such file or directory", path), "missing curve file");
    rc = run("eval %s/scene --curves %s --loss edges", tmp, path);
    CHECK(ANSWER(1, rc, "%s: cannot open: No such file or directory", path), "eval: missing curves");
    CHECK(no_partial_outputs(out), "outputs after a bad curve file");
}

/* What is wrong with the ground truth eval measures against, or with a
 * sketch that has nothing to measure, names the file. */
static void test_ground_truth_files(void) {
    char sketch[400], gt[400];
    snprintf(sketch, sizeof sketch, "%s/scene/gt_curves.json", tmp);
    snprintf(gt, sizeof gt, "%s/gt.json", tmp);
    write_text(gt, "{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": []}");
    int rc = run("eval %s/scene --curves %s --loss none --gt-curves %s", tmp, sketch, gt);
    CHECK(ANSWER(1, rc, "%s: curve metrics: the ground truth has no curves", gt), "eval: ground truth without curves");
    write_text(gt, "{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": [[[1, 1, 1], [1, 1, 1], [1, 1, 1], [1, 1, 1]]]}");
    rc = run("eval %s/scene --curves %s --loss none --gt-curves %s", tmp, sketch, gt);
    CHECK(ANSWER(1, rc, "%s: curve metrics: the ground-truth curves have a zero-diagonal bounding box", gt),
          "eval: ground-truth curves without extent");
    snprintf(gt, sizeof gt, "%s/gt.ply", tmp);
    write_text(gt, "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n1 1 1\n1 1 1\n");
    rc = run("eval %s/scene --curves %s --loss none --gt %s", tmp, sketch, gt);
    CHECK(ANSWER(1, rc, "%s: ground-truth points: the bounding box has a zero diagonal", gt),
          "eval: ground-truth points without extent");
    snprintf(sketch, sizeof sketch, "%s/empty.json", tmp);
    write_text(sketch, "{\"thickness\": 0.02, \"overlap\": 0.6, \"curves\": []}");
    rc = run("eval %s/scene --curves %s --loss none", tmp, sketch);
    CHECK(ANSWER(1, rc, "%s: no curves to measure against the ground truth", sketch), "eval: sketch without curves");
}

/* The layout of a checkpoint (checkpoint.h): the offsets of the curve
 * count and the first control point, after the stored arguments. */
static void checkpoint_offsets(const unsigned char *c, size_t *curves_at, size_t *points_at) {
    size_t pos = 12;
    uint32_t argc = get_u32(c + pos);
    pos += 4;
    for (uint32_t i = 0; i < argc; i++) pos += 4 + get_u32(c + pos);
    pos += 3 * 4 + 8 + 4 + 8 + 8 + 32; /* schedule, elapsed, skipped, rng */
    pos += 4 + 4 * (size_t)get_u32(c + pos); /* view order */
    *curves_at = pos;
    *points_at = pos + 4 + 16;
}

/* Writes checkpoint c with its stored arguments replaced by argv[0..n) and
 * the checksum made right: a crafted file the loader's checks all pass. */
static int write_with_arguments(const char *path, const unsigned char *c, size_t len,
                                const char *const *argv, int n) {
    size_t old_end = 16;
    for (uint32_t i = 0, count = get_u32(c + 12); i < count; i++) old_end += 4 + get_u32(c + old_end);
    size_t args = 4;
    for (int i = 0; i < n; i++) args += 4 + strlen(argv[i]);
    size_t out_len = 12 + args + (len - old_end);
    unsigned char *out = malloc(out_len);
    if (!out) return 0;
    memcpy(out, c, 12);
    size_t pos = 12;
    put_u32(out + pos, (uint32_t)n);
    pos += 4;
    for (int i = 0; i < n; i++) {
        put_u32(out + pos, (uint32_t)strlen(argv[i]));
        memcpy(out + pos + 4, argv[i], strlen(argv[i]));
        pos += 4 + strlen(argv[i]);
    }
    memcpy(out + pos, c + old_end, len - old_end);
    fix_crc(out, out_len);
    int ok = write_all(path, out, out_len);
    free(out);
    return ok;
}

/* Stored arguments are input: a crafted list goes through the same parse
 * and checks as a command line (a NULL scene once crashed here). */
static void test_stored_arguments(const unsigned char *c, size_t len) {
    char dir[300], path[400], scene[300];
    snprintf(dir, sizeof dir, "%s/ck_args", tmp);
    snprintf(scene, sizeof scene, "%s/scene", tmp);
    sh("mkdir -p %s", dir);
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    const char *resume[] = {"--resume", dir};
    write_with_arguments(path, c, len, resume, 2);
    int rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: stored arguments contain --resume", path), "stored --resume");
    const char *no_scene[] = {"--loss", "edges"};
    write_with_arguments(path, c, len, no_scene, 2);
    rc = run("fit --resume %s", dir);
    CHECK(rc == 1 && sh("grep -q '^wiresketch: %s: stored arguments: fit: missing SCENE' %s/stderr.txt",
                        path, tmp),
          "stored arguments without a scene");
    const char *bad_epochs[] = {scene, "--loss", "edges", "--epochs", "-5"};
    write_with_arguments(path, c, len, bad_epochs, 5);
    rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: stored arguments: --epochs: -5 is not in [0, 1000000]", path),
          "stored --epochs -5");
    const char *many_threads[] = {scene, "--loss", "edges", "--threads", "100000"};
    write_with_arguments(path, c, len, many_threads, 5);
    rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: stored arguments: --threads: 100000 is not in [0, 1024] (0: one per core)",
                 path),
          "stored --threads 100000");
    /* an override is checked as the command line it is */
    const char *good[] = {scene, "--loss", "edges", "--size", "32", "--threads", "1", "--quiet"};
    write_with_arguments(path, c, len, good, 8);
    rc = run("fit --resume %s --max-steps -5", dir);
    CHECK(ANSWER(2, rc, "--max-steps, --eval-every and --snapshot-every must be >= 0"), "override out of range");
    CHECK(checkpoint_loads(path), "the refused checkpoint was damaged");
}

static void test_checkpoints(void) {
    char dir[300], path[400];
    snprintf(dir, sizeof dir, "%s/nowhere", tmp);
    int rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s/checkpoint.bin: no checkpoint to resume from", dir), "no checkpoint");
    snprintf(dir, sizeof dir, "%s/ck_base", tmp);
    CHECK(run("fit %s/scene --out %s " FIT, tmp, dir) == 0, "base fit failed");
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    size_t len;
    unsigned char *c = (unsigned char *)slurp(path, &len);
    CHECK(c && len > 200, "no checkpoint written");
    if (!c || len <= 200) return;
    size_t curves_at, points_at;
    checkpoint_offsets(c, &curves_at, &points_at);
    snprintf(dir, sizeof dir, "%s/ck_bad", tmp);
    sh("mkdir -p %s", dir);
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    /* truncated: the checksum no longer matches; below the header */
    write_all(path, c, len - 10);
    rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: checksum mismatch (the file is damaged)", path), "cut checkpoint");
    write_all(path, c, 12);
    rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: not a wiresketch checkpoint", path), "stub checkpoint");
    /* wrong magic */
    write_edited(path, c, len, 0, "WSKCLIP", 7);
    rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: not a wiresketch checkpoint", path), "weight file as checkpoint");
    /* NaN control point; a curve count of 2^32 - 1 (checksums right) */
    const double nan = NAN;
    write_edited(path, c, len, points_at + 8 * 5, &nan, 8);
    rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: corrupt checkpoint (non-finite control point)", path), "NaN point");
    const unsigned char all_ones[4] = {0xff, 0xff, 0xff, 0xff};
    write_edited(path, c, len, curves_at, all_ones, 4);
    rc = run("fit --resume %s", dir);
    CHECK(ANSWER(1, rc, "%s: corrupt checkpoint (curves)", path), "huge curve count");
    CHECK(no_partial_outputs(dir), "outputs after a bad checkpoint");
    test_stored_arguments(c, len);
    free(c);
    /* a checkpoint of another scene (wrong shape: 2 training views, not 3) */
    const char *s = scene_copy("s_changed");
    snprintf(dir, sizeof dir, "%s/ck_changed", tmp);
    CHECK(run("fit %s --out %s " FIT, s, dir) == 0, "fit of the scene copy failed");
    CHECK(sh("%s scene trefoil --out %s --size 32 --views-train 2 --views-val 1 --views-test 1 "
             ">/dev/null 2>&1", program_path(), s), "scene rewrite failed");
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    rc = run("fit --resume %s --max-steps 4", dir);
    CHECK(ANSWER(1, rc, "%s: made for 3 training views, the scene has 2", path), "other scene");
    CHECK(checkpoint_loads(path), "the refused checkpoint was damaged");
}

/* A directory writes fail in: chmod 0555 when that stops this process (not
 * root), else a read-only tmpfs mounted on it (root). Returns the errno a
 * write gets, 0 when neither works. */
static int make_read_only(const char *dir) {
    sh("mkdir -p %s", dir);
    chmod(dir, 0555);
    if (access(dir, W_OK) != 0) return EACCES;
    if (sh("mount -t tmpfs -o ro,size=64k tmpfs %s 2>/dev/null", dir)) return EROFS;
    return 0;
}

static void test_output_faults(void) {
    char dir[300], path[400];
    /* the output directory is read-only */
    snprintf(dir, sizeof dir, "%s/read_only", tmp);
    int err = make_read_only(dir);
    if (err) {
        int rc = run("fit %s/scene --out %s " FIT, tmp, dir);
        CHECK(ANSWER(1, rc, "%s/checkpoint.bin: cannot write: %s", dir, strerror(err)),
              "read-only output directory");
        CHECK(no_partial_outputs(dir) && !sh("test -e %s/checkpoint.bin", dir), "outputs in a read-only dir");
        if (err == EROFS) sh("umount %s", dir);
    } else {
        printf("note: read-only directory skipped: chmod does not stop root here and no tmpfs mounts\n");
    }
    chmod(dir, 0755);
    /* the output path is a file; its parent does not exist */
    snprintf(path, sizeof path, "%s/a_file", tmp);
    write_text(path, "x");
    int rc = run("fit %s/scene --out %s " FIT, tmp, path);
    CHECK(ANSWER(1, rc, "%s: exists and is not a directory", path), "--out names a file");
    snprintf(dir, sizeof dir, "%s/no/such/dir", tmp);
    rc = run("fit %s/scene --out %s " FIT, tmp, dir);
    CHECK(ANSWER(1, rc, "%s: cannot create directory: No such file or directory", dir), "--out parent");
    /* a full disk while writing the outputs: files may not grow past 40 KB
     * (the checkpoints and the other outputs, up to 30 KB, fit; the report,
     * about 48 KB, does not) */
    snprintf(dir, sizeof dir, "%s/full", tmp);
    rc = run_limited(40 << 10, "fit %s/scene --out %s " FIT, tmp, dir);
    snprintf(path, sizeof path, "%s/report.html", dir);
    CHECK(ANSWER(1, rc, "%s: write failed: File too large", path) && access(path, F_OK) != 0,
          "full disk during the outputs");
    CHECK(!sh("test -n \"$(find %s -name '*.tmp.*')\"", dir), "temporary files left on a full disk");
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    CHECK(checkpoint_loads(path), "the checkpoint did not survive the full disk");
    /* the file size limit while checkpointing: each step adds a snapshot
     * to the checkpoint until it no longer fits; the fit stops as on SIGINT
     * (128 + SIGXFSZ, test_signals.c), writing the outputs that fit; the
     * previous checkpoint stays whole and the fit resumes from it once
     * there is room */
    snprintf(dir, sizeof dir, "%s/full_ckpt", tmp);
    rc = run_limited(16 << 10, "fit %s/scene --out %s --loss edges --size 32 --threads 1 --quiet "
                     "--max-steps 40 --snapshot-every 1 --checkpoint-minutes 0.00001", tmp, dir);
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    CHECK(ANSWER(153, rc, "stopped by SIGXFSZ (the file size limit, ulimit -f); %s: write failed: File too large; "
                 "what could be written is in %s; continue with `wiresketch fit --resume %s`", path, dir, dir),
          "file size limit at a checkpoint");
    CHECK(!sh("test -n \"$(find %s -name '*.tmp.*')\"", dir), "temporary files left at a checkpoint");
    CHECK(checkpoint_loads(path), "the last checkpoint was damaged by the full disk");
    rc = run("fit --resume %s", dir);
    CHECK(rc == 0, "resume after the full disk failed");
    /* a PNG that does not fit: named, with the reason from errno */
    snprintf(dir, sizeof dir, "%s/full_png", tmp);
    rc = run_limited(512, "render %s/scene/gt_curves.json --scene %s/scene --out %s --size 200", tmp, tmp,
                     dir);
    CHECK(ANSWER(1, rc, "%s/r_0.png: write failed: File too large", dir), "full disk in a PNG");
    CHECK(no_partial_outputs(dir), "outputs after a failed PNG");
    /* a real full disk, when a tmpfs can be mounted (root) */
    snprintf(dir, sizeof dir, "%s/tmpfs", tmp);
    sh("mkdir -p %s", dir);
    if (sh("mount -t tmpfs -o size=40k tmpfs %s 2>/dev/null", dir)) {
        rc = run("fit %s/scene --out %s/out " FIT, tmp, dir);
        snprintf(path, sizeof path, "%s/stderr.txt", tmp);
        CHECK(rc == 1 && sh("grep -q ': write failed: No space left on device$' %s", path) &&
                  sh("test $(wc -l < %s) -eq 1", path) &&
                  !sh("test -n \"$(find %s -name '*.tmp.*')\"", dir),
              "full tmpfs");
        snprintf(path, sizeof path, "%s/out/checkpoint.bin", dir);
        CHECK(checkpoint_loads(path), "checkpoint on the full tmpfs");
        sh("umount %s", dir);
    } else {
        printf("note: full tmpfs skipped (cannot mount here); RLIMIT_FSIZE cases above ran\n");
    }
}

/* Finite weights of 3e38 make CLIP's activations overflow: every step's
 * loss is not finite and is refused before it reaches the control points,
 * which stay where they started (the checkpoint's first snapshot). */
static void test_numeric_faults(void) {
    size_t len;
    unsigned char *w = (unsigned char *)slurp("tests/fuzz/corpus/weights/tiny_f32.bin", &len);
    if (!w) return;
    size_t data = (size_t)w[WF_ENTRY0 + 104] | (size_t)w[WF_ENTRY0 + 105] << 8;
    size_t nbytes = (size_t)w[WF_ENTRY0 + 112] | (size_t)w[WF_ENTRY0 + 113] << 8;
    float *huge = malloc(nbytes);
    for (size_t i = 0; i < nbytes / 4; i++) huge[i] = 3e38f;
    char path[400], dir[300], want[1024];
    snprintf(path, sizeof path, "%s/w_overflow.bin", tmp);
    write_edited(path, w, len, data, huge, nbytes);
    free(huge);
    free(w);
    int rc = run("embed --weights %s %s/scene/rgb/train/r_0.png", path, tmp);
    CHECK(ANSWER(1, rc, "%s: the forward pass produced a non-finite value", path), "embed overflows");
    snprintf(dir, sizeof dir, "%s/overflow", tmp);
    run("fit %s/scene --out %s --loss clip --weights %s --size 8 --clip-conv-layer-weights 1 "
        "--num-aug 0 --max-steps 3 --eval-every 0 --threads 1 --quiet", tmp, dir, path);
    for (int step = 0; step < 3; step++) {
        snprintf(want, sizeof want, "grep -qx 'wiresketch: step %d: non-finite loss or gradient "
                                    "(%s: the forward pass produced a non-finite value); step "
                                    "skipped' %s/stderr.txt", step, path, tmp);
        CHECK(sh("%s", want), "step %d: the non-finite loss was not reported", step);
    }
    ws_fit_state s;
    ws_status st = {0};
    int argc;
    char **argv;
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    CHECK(ws_checkpoint_load(path, &s, &argc, &argv, &st) == WS_OK, "%s", st.msg);
    if (st.code) return;
    CHECK(s.global_step == 3 && s.skipped_steps == 3, "%ld steps, %ld skipped", s.global_step,
          s.skipped_steps);
    size_t curve_bytes = (size_t)s.curves.n * WS_CURVE_FLOATS * sizeof(double);
    CHECK(s.nsnap >= 1 && !memcmp(s.curves.P, s.snapshots, curve_bytes),
          "a refused step moved the control points");
    int moments = 1;
    for (int i = 0; i < s.curves.n * WS_CURVE_FLOATS; i++) moments &= s.adam.m[i] == 0 && s.adam.v[i] == 0;
    CHECK(moments && s.adam.step == 0, "a refused step reached Adam's moments");
    ws_fit_state_free(&s);
    ws_checkpoint_free_args(argc, argv);
}

/* Fits that could only fail are refused before the first step: options
 * out of range, an --init without curves. */
static void test_hopeless_fits(void) {
    char out[300], path[400];
    snprintf(out, sizeof out, "%s/out_hopeless", tmp);
    int rc = run("fit %s/scene --out %s " FIT " --length 1e200", tmp, out);
    CHECK(ANSWER(2, rc, "--length: 1e+200 is not in [0, 1e+06]"), "--length 1e200");
    rc = run("fit %s/scene --out %s " FIT " --batch-size 2147483647", tmp, out);
    CHECK(ANSWER(2, rc, "--batch-size: 2147483647 is not in [1, 1000000]"), "huge --batch-size");
    /* 100 000 threads overflowed libgomp's stack; the bound is WS_MAX_THREADS */
    rc = run("fit %s/scene --out %s --loss edges --size 32 --quiet --threads 100000", tmp, out);
    CHECK(ANSWER(2, rc, "--threads: 100000 is not in [0, 1024] (0: one per core)"), "fit --threads 100000");
    rc = run("grad %s/scene --curves %s/scene/gt_curves.json --loss edges --size 32 --threads 100000", tmp,
             tmp);
    CHECK(ANSWER(2, rc, "--threads: 100000 is not in [0, 1024] (0: one per core)"), "grad --threads 100000");
    rc = run("fit %s/scene --out %s " FIT " --overlap 1", tmp, out);
    CHECK(ANSWER(2, rc, "--overlap: 1 is not in [0, 1)"), "--overlap 1");
    rc = run("fit %s/scene --out %s " FIT " --clip-geometric maps", tmp, out);
    CHECK(ANSWER(2, rc, "--clip-geometric: 'maps' is not blocks or attention"), "--clip-geometric maps");
    rc = run("fit %s/scene --out %s " FIT " --precision fp16", tmp, out);
    CHECK(ANSWER(2, rc, "--precision: 'fp16' is not fp32, bf16 or auto"), "fit --precision fp16");
    rc = run("bench clip --precision BF16");
    CHECK(ANSWER(2, rc, "--precision: 'BF16' is not fp32, bf16 or auto"), "bench --precision BF16");
    rc = run("fit %s/scene --out %s " FIT " --hidden-lines hidden", tmp, out);
    CHECK(ANSWER(2, rc, "--hidden-lines: 'hidden' is not hull or none"), "fit --hidden-lines hidden");
    rc = run("rank %s/scene --size 32 --hidden-lines Hull", tmp);
    CHECK(ANSWER(2, rc, "--hidden-lines: 'Hull' is not hull or none"), "rank --hidden-lines Hull");
    CHECK(run("scene trefoil --out %s/scene_noval --size 32 --views-train 3 --views-val 0 --views-test 1", tmp) == 0,
          "scene without validation views failed");
    rc = run("rank %s/scene_noval --size 32 --split val", tmp);
    CHECK(ANSWER(2, rc, "rank: the val split has no views"), "rank of an empty split");
    rc = run("fit %s/scene --out %s " FIT " --edges-weight -1", tmp, out);
    CHECK(ANSWER(2, rc, "loss weights (--clip-weight, --clip-conv-loss, --clip-fc-loss-weight, "
                        "--clip-conv-layer-weights, --edges-weight) must be >= 0"),
          "negative loss weight");
    rc = run("fit %s/scene --out %s " FIT " --silhouette-weight -0.5", tmp, out);
    CHECK(ANSWER(2, rc, "--silhouette-weight: -0.5 is not a finite number >= 0"), "negative --silhouette-weight");
    CHECK(access(out, F_OK) != 0, "a fit with options out of range created its output directory");
    snprintf(path, sizeof path, "%s/empty.json", tmp);
    write_text(path, "{\"thickness\": 0.5, \"overlap\": 0, \"curves\": []}");
    rc = run("fit %s/scene --out %s " FIT " --init %s", tmp, out, path);
    CHECK(ANSWER(1, rc, "%s: no curves (a fit starts from at least one)", path), "empty --init");
    CHECK(no_partial_outputs(out), "outputs after a hopeless fit");
}

static void test_usage(void) {
    int rc = run("fit x --no-such-option 1");
    CHECK(ANSWER(2, rc, "--no-such-option: unknown option (see --help)"), "unknown option");
    rc = run("fit x --epochs many");
    CHECK(ANSWER(2, rc, "--epochs: 'many' is not an integer or 'auto'"), "bad integer");
    rc = run("fit x --learning-rate nan");
    CHECK(ANSWER(2, rc, "--learning-rate: 'nan' is not a finite number"), "NaN option");
    rc = run("fit --quiet");
    CHECK(rc == 2 && sh("grep -q '^wiresketch: fit: missing SCENE (usage: ' %s/stderr.txt", tmp),
          "missing SCENE");
    rc = run("frobnicate");
    CHECK(ANSWER(2, rc, "frobnicate: unknown command (see wiresketch --help)"), "unknown command");
}

int main(void) {
    tmp = test_tmpdir("bad_input");
    CHECK(run("scene trefoil --out %s/scene --size 32 --views-train 3 --views-val 1 --views-test 1",
              tmp) == 0,
          "scene generation failed");
    test_scenes();
    test_pngs();
    test_special_files();
    test_weights();
    test_curve_files();
    test_ground_truth_files();
    test_checkpoints();
    test_output_faults();
    test_numeric_faults();
    test_hopeless_fits();
    test_usage();
    return check_summary();
}
