/* test_random_weights.c: tools/make_random_weights.py, which makes the
 * weight files of `make bench` (nothing else runs it), on a small
 * architecture: the files load in the C reader and model, every tensor
 * has the centre and spread of clip_model_random's scales, the same seed
 * gives the same bytes and another seed others, the f16 file is the f32
 * one rounded to half precision, the model runs, and a bad architecture or
 * output path is refused with one line. Needs python3 (standard library). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_util.h"
#include "nn/clip.h"
#include "nn/weightfile.h"

#define TOOL "python3 tools/make_random_weights.py"
#define SMALL "--width 64 --layers 2 --heads 4 --patch 16 --resolution 64 --output-dim 32"

static const char *dir;

/* dir/name made with extra options; 0 when the tool succeeded. */
static int make(const char *name, const char *options) {
    char out[4096];
    int rc = run_cmd(out, sizeof out, TOOL " %s/%s " SMALL " %s", dir, name, options);
    CHECK(rc == 0, "make_random_weights %s (exit %d): %s", options, rc, out);
    return rc;
}

/* dir/a and dir/b hold the same bytes. */
static int same_weights(const char *a, const char *b) {
    char pa[300], pb[300];
    snprintf(pa, sizeof pa, "%s/%s", dir, a);
    snprintf(pb, sizeof pb, "%s/%s", dir, b);
    return same_file(pa, pb);
}

/* clip_model_random's (centre, standard deviation) of a tensor of the
 * small model (width 64, 2 layers, patch 16), as nn/clip.c lists them. */
static void expected_scale(const char *name, double *centre, double *std) {
    const double w = 64, layers = 2, patch = 16;
    size_t n = strlen(name);
    int is_ln = strstr(name, "ln_") != NULL, is_bias = n > 4 && !strcmp(name + n - 4, "bias");
    *centre = 0;
    if (is_ln) {
        *centre = is_bias ? 0.0 : 1.0;
        *std = 0.1;
    } else if (!strcmp(name, "conv1.weight")) {
        *std = 1 / sqrt(3 * patch * patch);
    } else if (strstr(name, "out_proj.weight") || strstr(name, "c_proj.weight")) {
        *std = 1 / sqrt(w) / sqrt(2 * layers);
    } else if (strstr(name, "c_fc.weight")) {
        *std = 1 / sqrt(2 * w);
    } else if (is_bias) {
        *std = 0.02;
    } else {
        *std = 1 / sqrt(w);
    }
}

/* Every tensor's values within its uniform range, mean and spread near
 * the expected ones (uniform draws: the sample's standard error). */
static void test_values(const wf_file *f) {
    int bad = 0;
    for (int i = 0; i < wf_count(f); i++) {
        const wf_tensor *t = wf_tensor_at(f, i);
        double centre, std, sum = 0, sq = 0, half;
        expected_scale(t->name, &centre, &std);
        half = sqrt(3.0) * std;
        int outside = 0;
        for (int64_t k = 0; k < t->numel; k++) {
            double v = t->data[k] - centre;
            outside += fabs(v) > half * (1 + 1e-6);
            sum += v;
            sq += v * v;
        }
        double mean = sum / (double)t->numel, sd = sqrt(sq / (double)t->numel - mean * mean);
        double se = std / sqrt((double)t->numel);
        if (outside || fabs(mean) > 5 * se + 1e-7 || fabs(sd - std) > 0.25 * std) {
            CHECK(0, "%s: %d values outside +-%g, mean %g (expected %g), sd %g (expected %g)", t->name,
                  outside, half, mean + centre, centre, sd, std);
            bad++;
        }
    }
    CHECK(!bad && wf_count(f) == 5 + 12 * 2 + 3, "%d tensors, %d off their scales", wf_count(f), bad);
}

/* The f16 file holds the f32 file's values rounded to half precision:
 * each within half a unit in the last place of f16 (2^-11 relative), and
 * not all equal (it is f16). */
static void test_f16(const wf_file *f32, const wf_file *f16) {
    double worst = 0;
    int64_t differ = 0, n = 0;
    for (int i = 0; i < wf_count(f32) && i < wf_count(f16); i++) {
        const wf_tensor *a = wf_tensor_at(f32, i), *b = wf_tensor_at(f16, i);
        if (strcmp(a->name, b->name) || a->numel != b->numel || b->dtype != WF_F16) {
            CHECK(0, "f16 file: tensor %d is %s (dtype %d), not %s", i, b->name, b->dtype, a->name);
            return;
        }
        for (int64_t k = 0; k < a->numel; k++, n++) {
            double d = fabs((double)a->data[k] - b->data[k]);
            worst = fmax(worst, d / (fabs(a->data[k]) * 0x1p-11 + 0x1p-25));
            differ += d > 0;
        }
    }
    CHECK(n > 0 && worst <= 1.0 && differ > n / 2,
          "f16 file: %lld of %lld values differ, worst error %g half-ulps", (long long)differ, (long long)n,
          worst);
}

/* Both files load as models that run, and agree to f16 precision. */
static void test_models(void) {
    char path[2][300];
    clip_model *m[2] = {NULL, NULL};
    clip_run *r[2] = {NULL, NULL};
    ws_status st;
    ws_status_clear(&st);
    for (int k = 0; k < 2; k++) {
        snprintf(path[k], sizeof path[k], "%s/%s", dir, k ? "f16.bin" : "a.bin");
        clip_run_options opt = {1, 1, 1, 0, 0};
        CHECK(clip_model_load(&m[k], path[k], &st) == WS_OK && clip_run_create(&r[k], m[k], &opt, &st) == WS_OK,
              "%s", st.msg);
        if (st.code) goto done;
    }
    enum { PIXELS = 3 * 64 * 64 };
    static float image[PIXELS];
    for (int i = 0; i < PIXELS; i++) image[i] = (float)((i * 7919 % 1000) / 1000.0);
    for (int k = 0; k < 2; k++) CHECK(clip_forward(r[k], image, &st) == WS_OK, "%s", st.msg);
    if (st.code) goto done;
    double norm = 0, diff = 0;
    for (int i = 0; i < 32; i++) {
        double a = clip_embedding(r[0])[i], b = clip_embedding(r[1])[i];
        norm += a * a;
        diff += (a - b) * (a - b);
    }
    CHECK(isfinite(norm) && norm > 1e-6 && sqrt(diff / norm) < 1e-2,
          "embeddings: norm^2 %g, f16 against f32 relative %g", norm, sqrt(diff / norm));
done:
    for (int k = 0; k < 2; k++) {
        clip_run_free(r[k]);
        clip_model_free(m[k]);
    }
}

static void test_errors(void) {
    char out[4096];
    CHECK(run_cmd(out, sizeof out, TOOL " %s/x.bin --width 60 --heads 8", dir) == 2 &&
              !strcmp(out, "make_random_weights.py: --width 60 is not a multiple of --heads 8\n"),
          "width and heads: %s", out);
    CHECK(run_cmd(out, sizeof out, TOOL " %s/x.bin --resolution 100", dir) == 2 &&
              !strcmp(out, "make_random_weights.py: --resolution 100 is not a multiple of --patch 32\n"),
          "resolution and patch: %s", out);
    CHECK(run_cmd(out, sizeof out, TOOL " %s/x.bin --layers 0", dir) == 2 &&
              !strcmp(out, "make_random_weights.py: --layers 0: must be at least 1\n"),
          "no layers: %s", out);
    char expect[400];
    snprintf(expect, sizeof expect, "make_random_weights.py: %s/none/x.bin: cannot write (No such file or directory)\n", dir);
    CHECK(run_cmd(out, sizeof out, TOOL " %s/none/x.bin " SMALL, dir) == 1 && !strcmp(out, expect),
          "missing folder: %s", out);
}

int main(void) {
    dir = test_tmpdir("random_weights");
    if (make("a.bin", "--seed 5") || make("b.bin", "--seed 5") || make("c.bin", "--seed 6") ||
        make("f16.bin", "--seed 5 --dtype f16"))
        return check_summary();
    CHECK(same_weights("a.bin", "b.bin"), "the same seed gave other bytes");
    CHECK(!same_weights("a.bin", "c.bin"), "another seed gave the same bytes");
    char path[300];
    wf_file *f32 = NULL, *f16 = NULL;
    ws_status st;
    ws_status_clear(&st);
    snprintf(path, sizeof path, "%s/a.bin", dir);
    CHECK(wf_open(&f32, path, &st) == WS_OK, "%s", st.msg);
    snprintf(path, sizeof path, "%s/f16.bin", dir);
    CHECK(wf_open(&f16, path, &st) == WS_OK, "%s", st.msg);
    if (f32 && f16) {
        const wf_arch *a = wf_architecture(f32);
        CHECK(a->width == 64 && a->layers == 2 && a->heads == 4 && a->patch == 16 && a->resolution == 64 &&
                  a->output_dim == 32,
              "architecture %d %d %d %d %d %d", a->width, a->layers, a->heads, a->patch, a->resolution,
              a->output_dim);
        test_values(f32);
        test_f16(f32, f16);
    }
    wf_close(f32);
    wf_close(f16);
    test_models();
    test_errors();
    return check_summary();
}
