/* test_render.c: the render, grad and export commands through the CLI binary
 * ($BUILD/wiresketch, BUILD from tests/run.sh, default build) on the
 * committed fixture scene (or, given a scenes folder as argument, as by
 * `make test-scenes`, on its rose): file names, PNG format, content against the library's own splat,
 * the gradient JSON, the export files, and the command-line errors. */
#include <cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include "nn/base/bytes.h"
#include "check.h"
#include "test_util.h"
#include "render/curves.h"
#include "io/image.h"
#include "objective/loss_l2.h"
#include "io/scene.h"
#include "render/splat.h"

static char SCENE[1024] = "tests/fixtures/scene_small";
static const char *bin, *tmp;

/* The bytes of a PNG's IHDR: width, height, bit depth, colour type. */
static int png_header(const char *path, unsigned *w, unsigned *h, int *depth, int *type) {
    unsigned char b[29];
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    size_t n = fread(b, 1, sizeof b, f);
    fclose(f);
    if (n != sizeof b || memcmp(b, "\x89PNG\r\n\x1a\n", 8) || memcmp(b + 12, "IHDR", 4)) return 0;
    *w = (unsigned)b[16] << 24 | b[17] << 16 | b[18] << 8 | b[19];
    *h = (unsigned)b[20] << 24 | b[21] << 16 | b[22] << 8 | b[23];
    *depth = b[24];
    *type = b[25];
    return 1;
}

/* A sketch of 8 curves around the scene centre. */
static void make_curves(const ws_scene *scene, ws_curves *c) {
    ws_status st;
    ws_rng rng;
    ws_rng_seed(&rng, 21);
    ws_curves_alloc(c, 8, &st);
    c->thickness = 0.02;
    c->overlap = 0.6;
    for (int ci = 0; ci < 8; ci++)
        for (int j = 0; j < 4; j++)
            for (int x = 0; x < 3; x++)
                c->P[ci * WS_CURVE_FLOATS + j * 3 + x] =
                    scene->center[x] + 0.25 * ws_rng_normal(&rng) + 0.1 * j * (x == ci % 3);
}

static void test_render(const ws_scene *scene, const ws_curves *c, const char *curves_path) {
    char out[4096], dir[512];
    snprintf(dir, sizeof dir, "%s/render", tmp);
    int rc = run_cmd(out, sizeof out, "%s render %s --scene %s --split test --out %s --alpha", bin, curves_path,
                 SCENE, dir);
    CHECK(rc == 0, "render exits 0: %d %s", rc, out);
    const ws_split *test = &scene->split[WS_TEST];
    ws_gaussians g = {0};
    ws_splat *s;
    ws_status st;
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    ws_curves_sample(c, &g, &st);
    ws_splat_create(&s, 224, 224, &st);
    double alpha[224 * 224];
    int named = 0, format = 0, match = 0, content = 0;
    for (int k = 0; k < test->n; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s.png", dir, test->views[k].name);
        unsigned w, h;
        int depth, type;
        if (!png_header(path, &w, &h, &depth, &type)) continue;
        named++;
        format += w == 224 && h == 224 && depth == 8 && type == 0;
        ws_image img;
        float black[3] = {0, 0, 0};
        if (ws_image_read(path, 0, 0, black, &img, &st)) continue;
        ws_splat_forward(s, &test->views[k].cam, g.mu, g.n, c->thickness, &opt, alpha, &st);
        double worst = 0, top = 0;
        for (int p = 0; p < 224 * 224; p++) {
            worst = fmax(worst, fabs(img.data[p] - round(255 * alpha[p]) / 255));
            top = fmax(top, img.data[p]);
        }
        match += worst < 1e-6;
        content += top > 0.9;
        ws_image_free(&img);
    }
    CHECK(test->n > 0 && named == test->n, "one PNG per test view, named after it: %d of %d",
          named, test->n);
    CHECK(format == test->n, "all 224 x 224 8-bit gray: %d of %d", format, test->n);
    CHECK(match == test->n, "every pixel is round(255 alpha) of the library's splat: %d of %d",
          match, test->n);
    CHECK(content == test->n, "every view shows strokes: %d of %d", content, test->n);
    char count[64];
    run_cmd(count, sizeof count, "ls %s | wc -l", dir);
    CHECK(atoi(count) == test->n, "no other files in the output directory: %s", count);

    /* without --alpha: black strokes on white, as the fit's test renders */
    rc = run_cmd(out, sizeof out, "%s render %s --scene %s --split test --out %s/drawn", bin, curves_path, SCENE, tmp);
    char path[1024];
    snprintf(path, sizeof path, "%s/drawn/%s.png", tmp, test->views[0].name);
    ws_image img;
    float black[3] = {0, 0, 0};
    if (rc == 0 && ws_image_read(path, 0, 0, black, &img, &st) == WS_OK) {
        ws_splat_forward(s, &test->views[0].cam, g.mu, g.n, c->thickness, &opt, alpha, &st);
        double worst = 0;
        for (int p = 0; p < 224 * 224; p++) worst = fmax(worst, fabs(img.data[p] - round(255 * (1 - alpha[p])) / 255));
        CHECK(worst < 1e-6, "render: every pixel is round(255 (1 - alpha)): off by %g", worst);
        ws_image_free(&img);
    } else {
        CHECK(0, "render without --alpha: %d %s", rc, out);
    }
    rc = run_cmd(out, sizeof out, "%s render %s --scene %s --split val --out %s/small --size 64 --cutoff inf",
             bin, curves_path, SCENE, tmp);
    unsigned w = 0, h = 0;
    int depth, type;
    snprintf(path, sizeof path, "%s/small/%s.png", tmp, scene->split[WS_VAL].views[0].name);
    CHECK(rc == 0 && png_header(path, &w, &h, &depth, &type) && w == 64 && h == 64,
          "render --split val --size 64 --cutoff inf: %d %s (%u x %u)", rc, out, w, h);
    ws_splat_free(s);
    ws_gaussians_free(&g);
}

/* grad prints the same numbers as the library chain computes here. */
static void test_grad(const ws_curves *c, const char *curves_path) {
    static char out[1 << 16];
    int rc = run_cmd(out, sizeof out, "%s grad %s --curves %s --split test --view 3 --loss l2", bin,
                 SCENE, curves_path);
    CHECK(rc == 0, "grad exits 0: %s", out);
    cJSON *root = cJSON_Parse(out);
    CHECK(root != NULL, "grad prints one JSON object");
    if (!root) return;
    ws_scene scene;
    ws_scene_options so;
    ws_status st;
    ws_scene_options_default(&so);
    CHECK(ws_scene_load(&scene, SCENE, &so, &st) == WS_OK, "scene with photos: %s", st.msg);
    const ws_view *v = &scene.split[WS_TEST].views[3];
    ws_gaussians g = {0};
    ws_splat *s;
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    ws_curves_sample(c, &g, &st);
    ws_splat_create(&s, 224, 224, &st);
    static double alpha[224 * 224], dalpha[224 * 224];
    double *dmu = malloc(sizeof(double) * 3 * g.n), dP[8 * WS_CURVE_FLOATS];
    ws_splat_forward(s, &v->cam, g.mu, g.n, c->thickness, &opt, alpha, &st);
    double L = ws_loss_l2_forward(alpha, v->photo.data, 224 * 224);
    memset(dalpha, 0, sizeof dalpha);
    ws_loss_l2_backward(alpha, v->photo.data, 224 * 224, 1.0, dalpha);
    ws_splat_backward(s, dalpha, dmu, &st);
    ws_curves_backward(c, &g, dmu, dP);
    const cJSON *jl = cJSON_GetObjectItem(root, "loss"), *jg = cJSON_GetObjectItem(root, "grad");
    CHECK(cJSON_IsNumber(jl) && jl->valuedouble == L, "loss printed exactly: %.17g", L);
    int same = cJSON_GetArraySize(jg) == 8, nonzero = 0;
    for (int ci = 0; ci < 8 && same; ci++)
        for (int j = 0; j < 4; j++)
            for (int x = 0; x < 3; x++) {
                const cJSON *num = cJSON_GetArrayItem(cJSON_GetArrayItem(cJSON_GetArrayItem(jg, ci), j), x);
                same &= num && num->valuedouble == dP[ci * WS_CURVE_FLOATS + j * 3 + x];
                nonzero += dP[ci * WS_CURVE_FLOATS + j * 3 + x] != 0;
            }
    CHECK(same, "gradient printed exactly (8 x 4 x 3)");
    CHECK(nonzero > 48, "the gradient has content: %d non-zero", nonzero);
    cJSON_Delete(root);
    free(dmu);
    ws_splat_free(s);
    ws_gaussians_free(&g);
    ws_scene_free(&scene);
}

static int count_lines(const char *path, const char *prefix) {
    char line[4096];
    int n = 0;
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    while (fgets(line, sizeof line, f)) n += !strncmp(line, prefix, strlen(prefix));
    fclose(f);
    return n;
}

static void test_export(const char *curves_path) {
    char out[4096], obj[512], ply[512], svg[512];
    snprintf(obj, sizeof obj, "%s/s.obj", tmp);
    snprintf(ply, sizeof ply, "%s/s.ply", tmp);
    snprintf(svg, sizeof svg, "%s/s.svg", tmp);
    int rc = run_cmd(out, sizeof out, "%s export %s --obj %s --ply %s --svg %s --scene %s --view 2 --drawing curves", bin,
                 curves_path, obj, ply, svg, SCENE);
    CHECK(rc == 0, "export exits 0: %s", out);
    CHECK(count_lines(obj, "v ") == 8 * 33 && count_lines(obj, "l ") == 8,
          "OBJ: 33 vertices and one polyline per curve");
    CHECK(count_lines(ply, "element vertex 264") == 1 && count_lines(ply, "element edge 256") == 1,
          "PLY: vertex and edge elements");
    CHECK(count_lines(svg, "<path ") == 8, "SVG: one path per curve (all in front)");
    /* the last OBJ vertex of curve 0 is its end point P3 */
    ws_curves c;
    ws_status st;
    ws_curves_load(curves_path, &c, &st);
    FILE *f = fopen(obj, "r");
    char line[256];
    double x = 0, y = 0, z = 0;
    for (int k = 0; k < 34 && fgets(line, sizeof line, f);)
        if (line[0] == 'v' && ++k == 33) sscanf(line, "v %lf %lf %lf", &x, &y, &z);
    fclose(f);
    CHECK(fabs(x - c.P[9]) < 1e-6 && fabs(y - c.P[10]) < 1e-6 && fabs(z - c.P[11]) < 1e-6,
          "OBJ polyline ends at P3");
    ws_curves_free(&c);
    rc = run_cmd(out, sizeof out, "%s export %s --svg %s", bin, curves_path, svg);
    CHECK(rc == 2 && strstr(out, "wiresketch: --scene: required"), "--svg needs --scene: %s", out);
}

/* Every command-line mistake is one line and the right exit code. */
/* `text` with SCENE, NTEST and LAST replaced by the scene directory, the
 * number of test views and the last test view's index. */
static void fill_in(char *out, size_t size, const char *text, int ntest) {
    char num[2][16];
    snprintf(num[0], sizeof num[0], "%d", ntest);
    snprintf(num[1], sizeof num[1], "%d", ntest - 1);
    const char *keys[3] = {"SCENE", "NTEST", "LAST"}, *vals[3] = {SCENE, num[0], num[1]};
    size_t n = 0;
    while (*text && n + 1 < size) {
        int k = 0;
        while (k < 3 && strncmp(text, keys[k], strlen(keys[k]))) k++;
        if (k == 3) {
            out[n++] = *text++;
            continue;
        }
        n += (size_t)snprintf(out + n, size - n, "%s", vals[k]);
        if (n >= size) n = size - 1;
        text += strlen(keys[k]);
    }
    out[n] = '\0';
}

static void test_errors(const char *curves_path, int ntest) {
    static const struct {
        const char *args;
        int code;
        const char *msg;
    } cases[] = {
        {"render %s --scene SCENE --out %s/x --bogus", 2, "wiresketch: --bogus: unknown option (see --help)\n"},
        {"render %s --scene SCENE --out %s/x --cutoff -1", 2, "wiresketch: --cutoff: '-1' must be positive or 'inf'\n"},
        {"render %s --scene SCENE --out %s/x --split dev", 2, "wiresketch: --split: 'dev' is not train, val or test\n"},
        {"render %s --scene SCENE --size 0 --out %s/x", 2, "wiresketch: --size: 0 is not in [1, 4096]\n"},
        {"render %s --out %s/x", 2, "wiresketch: --scene: required (see --help)\n"},
        {"render %s/nothere.json --scene SCENE --out %s", 1, "nothere.json: cannot open: No such file or directory\n"},
        {"grad SCENE --curves %s --view NTEST --loss l2%.0s", 2, "wiresketch: --view: NTEST is not in [0, LAST] (the test split has NTEST views)\n"},
        {"grad SCENE --curves %s --loss bogus%.0s", 2,
         "wiresketch: --loss: 'bogus' is not clip, edges, clip+edges, sobel or l2\n"},
        {"grad SCENE --curves %s --loss clip --weights %s/none.bin", 1, "none.bin: no CLIP weight file"},
        {"export %s --obj %s/nodir/x.obj", 1, "x.obj: cannot write"},
        {"export %s%.0s", 2, "wiresketch: nothing to do: give --obj, --ply or --svg (see --help)\n"},
    };
    char out[4096];
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char args[2048], fmt[2048], msg[2048];
        const char *first = strstr(cases[k].args, "%s/nothere") ? tmp : curves_path;
        fill_in(fmt, sizeof fmt, cases[k].args, ntest);
        fill_in(msg, sizeof msg, cases[k].msg, ntest);
        snprintf(args, sizeof args, fmt, first, tmp);
        int rc = run_cmd(out, sizeof out, "%s %s", bin, args);
        CHECK(rc == cases[k].code && strstr(out, msg) && strchr(out, '\n') == out + strlen(out) - 1,
              "`%s`: exit %d, got %d: %s", args, cases[k].code, rc, out);
    }
    const char *cmds[3] = {"render", "grad", "export"};
    for (int k = 0; k < 3; k++) {
        int rc = run_cmd(out, sizeof out, "%s %s --help", bin, cmds[k]);
        CHECK(rc == 0 && !strncmp(out, "usage: wiresketch ", 18), "%s --help: %s", cmds[k], out);
    }
}

int main(int argc, char **argv) {
    if (argc > 1) snprintf(SCENE, sizeof SCENE, "%s/rose", argv[1]);
    bin = program_path();
    tmp = test_tmpdir("render");
    CHECK(access(bin, X_OK) == 0, "%s exists (set BUILD)", bin);
    ws_scene scene;
    ws_scene_options so;
    ws_status st;
    ws_scene_options_default(&so);
    so.load_images = 0;
    if (ws_scene_load(&scene, SCENE, &so, &st)) {
        CHECK(0, "scene: %s", st.msg);
        return check_summary();
    }
    ws_curves c;
    make_curves(&scene, &c);
    char curves_path[512];
    snprintf(curves_path, sizeof curves_path, "%s/c.json", tmp);
    CHECK(ws_curves_save(curves_path, &c, &st) == WS_OK, "save curves: %s", st.msg);
    test_render(&scene, &c, curves_path);
    test_grad(&c, curves_path);
    test_export(curves_path);
    test_errors(curves_path, scene.split[WS_TEST].n);
    ws_curves_free(&c);
    ws_scene_free(&scene);
    return check_summary();
}
