/* test_clip_fixture.c: the image tower (clip.h) against PyTorch, through
 * every input format of the weight converter.
 *
 * tests/fixtures/clip_tiny/ (made by tools/make_fixtures.py) holds one small
 * CLIP (width 64, 2 layers, 4 heads, patch 16, resolution 64, output 32) as
 * OpenAI's TorchScript archive, a torch.save state dict and a Hugging Face
 * safetensors file, plus float64 reference values: every block output h_l,
 * the embedding e and the gradient of L = sum_l sum(h_l * C_l) + sum(e * C_e)
 * with respect to the [0, 1] input images (expected.*); every block's
 * attention probabilities P_l and the input gradient of
 * L = sum_l sum(P_l * D_l) (attention.*, the geometric loss's attention
 * variant).
 *
 * The test converts the three files itself (python3 tools/convert_weights.py,
 * standard library only) rather than keeping converted copies: one source of
 * truth, nothing to regenerate by hand, and the converter is exercised on
 * the real formats on every run. The three weight files must hold the same
 * numbers (the fixture's weights are f16-representable, so even the f16
 * file is exact); each must reproduce the reference. */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "nn/base/bytes.h"
#include "check.h"
#include "test_util.h"
#include "nn/clip.h"
#include "io/image.h"
#include "nn/weightfile.h"

#define FIXTURE "tests/fixtures/clip_tiny"

enum { MAX_LAYERS = 8, FORMATS = 3 };

typedef struct {
    const char *label, *input, *options, *file;
} format;

static const char *dir;
static char paths[FORMATS][300];
static const format formats[FORMATS] = {
    {"TorchScript archive", FIXTURE "/clip_tiny_torchscript.pt", "--heads 4", "torchscript.bin"},
    {"state dict (f16 weight file)", FIXTURE "/clip_tiny_state_dict.pt", "--heads 4 --dtype f16", "state_dict.bin"},
    {"safetensors", FIXTURE "/hf/model.safetensors", "", "safetensors.bin"},
};

/* The reference arrays: NAME.json indexes float32 arrays in NAME.bin. */
typedef struct {
    const char *name;
    cJSON *json;
    unsigned char *bin;
    size_t bin_len;
    wf_arch arch;
    int batch;
} reference;

static const float *array(const reference *ref, const char *name, size_t count) {
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(ref->json, "arrays"), name);
    const cJSON *offset = cJSON_GetObjectItemCaseSensitive(a, "offset");
    const cJSON *shape = cJSON_GetObjectItemCaseSensitive(a, "shape");
    size_t n = 1;
    const cJSON *d;
    cJSON_ArrayForEach(d, shape) n *= (size_t)d->valuedouble;
    int ok = cJSON_IsNumber(offset) && n == count && (size_t)offset->valuedouble % 4 == 0 &&
             (size_t)offset->valuedouble + 4 * n <= ref->bin_len;
    CHECK(ok, "%s.json: array %s missing or of the wrong size", ref->name, name);
    return ok ? (const float *)(ref->bin + (size_t)offset->valuedouble) : NULL;
}

static int int_field(const cJSON *obj, const char *name) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
    return cJSON_IsNumber(v) ? v->valueint : -1;
}

static int load_reference(reference *ref, const char *name) {
    ws_status st;
    ws_status_clear(&st);
    unsigned char *text;
    size_t len;
    char path[300];
    ref->name = name;
    snprintf(path, sizeof path, FIXTURE "/%s.json", name);
    CHECK(ws_read_file(path, 1 << 20, &text, &len, &st) == WS_OK, "%s", st.msg);
    if (st.code) return 1;
    ref->json = cJSON_ParseWithLength((const char *)text, len);
    free(text);
    CHECK(ref->json != NULL, "%s does not parse", path);
    snprintf(path, sizeof path, FIXTURE "/%s.bin", name);
    CHECK(ws_read_file(path, 1 << 24, &ref->bin, &ref->bin_len, &st) == WS_OK, "%s", st.msg);
    if (!ref->json || st.code) return 1;
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(ref->json, "arch");
    ref->arch = (wf_arch){int_field(a, "width"), int_field(a, "layers"), int_field(a, "heads"),
                          int_field(a, "patch"), int_field(a, "resolution"), int_field(a, "output_dim")};
    ref->batch = int_field(ref->json, "batch");
    CHECK(ref->arch.layers >= 1 && ref->arch.layers <= MAX_LAYERS && ref->batch >= 1,
          "%s.json: bad arch or batch", name);
    return ref->arch.layers < 1 || ref->arch.layers > MAX_LAYERS || ref->batch < 1;
}

/* max |got - want| / max |want|: the error relative to the array's scale. */
static double scaled_error(const float *got, const float *want, size_t n) {
    double err = 0, scale = 0;
    for (size_t i = 0; i < n; i++) {
        double e = fabs((double)got[i] - want[i]);
        err = isfinite(e) ? fmax(err, e) : INFINITY;
        scale = fmax(scale, fabs(want[i]));
    }
    return scale > 0 ? err / scale : err;
}

static int convert_all(void) {
    int ok = 1;
    for (int i = 0; i < FORMATS; i++) {
        snprintf(paths[i], sizeof paths[i], "%s/%s", dir, formats[i].file);
        char cmd[1024];
        snprintf(cmd, sizeof cmd, "python3 tools/convert_weights.py %s %s %s > /dev/null", formats[i].input,
                 paths[i], formats[i].options);
        int rc = system(cmd);
        CHECK(rc == 0, "converting the %s failed (%s: status %d)", formats[i].label, cmd, rc);
        ok &= rc == 0;
    }
    return ok;
}

/* All three files: the fixture's architecture and exactly the same numbers. */
static void test_same_weights(const reference *ref) {
    wf_file *f[FORMATS] = {NULL};
    ws_status st;
    ws_status_clear(&st);
    for (int i = 0; i < FORMATS; i++) {
        CHECK(wf_open(&f[i], paths[i], &st) == WS_OK, "%s", st.msg);
        if (st.code) goto done;
        const wf_arch *a = wf_architecture(f[i]);
        CHECK(memcmp(a, &ref->arch, sizeof *a) == 0, "%s: architecture %d %d %d %d %d %d", formats[i].label,
              a->width, a->layers, a->heads, a->patch, a->resolution, a->output_dim);
        CHECK(wf_count(f[i]) == 5 + 12 * ref->arch.layers + 3, "%s: %d tensors", formats[i].label,
              wf_count(f[i]));
    }
    for (int i = 1; i < FORMATS; i++) {
        int differ = wf_count(f[i]) != wf_count(f[0]);
        for (int k = 0; !differ && k < wf_count(f[0]); k++) {
            const wf_tensor *a = wf_tensor_at(f[0], k), *b = wf_tensor_at(f[i], k);
            differ = strcmp(a->name, b->name) != 0 || a->numel != b->numel ||
                     memcmp(a->data, b->data, (size_t)a->numel * sizeof(float)) != 0;
        }
        CHECK(!differ, "%s and %s hold different weights", formats[0].label, formats[i].label);
    }
    CHECK(wf_tensor_at(f[1], 0)->dtype == WF_F16 && wf_tensor_at(f[0], 0)->dtype == WF_F32,
          "the state dict was converted to f16, the others to f32");
done:
    for (int i = 0; i < FORMATS; i++) wf_close(f[i]);
}

static void test_model(const reference *ref, int which, const float *images) {
    const wf_arch *A = &ref->arch;
    const int B = ref->batch, T = 1 + (A->resolution / A->patch) * (A->resolution / A->patch);
    const size_t hidden_n = (size_t)B * T * A->width, image_n = (size_t)B * 3 * A->resolution * A->resolution;
    ws_status st;
    ws_status_clear(&st);
    clip_model *m = NULL;
    clip_run *r = NULL;
    float *d_images = malloc(image_n * sizeof *d_images);
    CHECK(clip_model_load(&m, paths[which], &st) == WS_OK, "%s", st.msg);
    clip_run_options opt = {B, A->layers - 1, 1, 1, 0};
    if (m) CHECK(clip_run_create(&r, m, &opt, &st) == WS_OK, "%s", st.msg);
    if (r) CHECK(clip_forward(r, images, &st) == WS_OK, "%s", st.msg);
    if (!r || st.code) goto done;
    CHECK(clip_attention(r, 0) == NULL, "%s: attention probabilities of a run without need_attention",
          formats[which].label);

    const float *d_hidden[MAX_LAYERS];
    for (int l = 0; l < A->layers; l++) {
        char name[32];
        snprintf(name, sizeof name, "hidden_%d", l);
        const float *want = array(ref, name, hidden_n);
        snprintf(name, sizeof name, "d_hidden_%d", l);
        d_hidden[l] = array(ref, name, hidden_n);
        if (!want || !d_hidden[l]) goto done;
        double err = scaled_error(clip_hidden(r, l), want, hidden_n);
        printf("%-30s h_%d   error %.2e\n", formats[which].label, l, err);
        CHECK(err <= 1e-5, "%s: h_%d differs from PyTorch by %.3g (relative to its largest value)",
              formats[which].label, l, err);
    }
    const float *e = array(ref, "embedding", (size_t)B * A->output_dim);
    const float *d_e = array(ref, "d_embedding", (size_t)B * A->output_dim);
    const float *want_grad = array(ref, "d_images", image_n);
    if (!e || !d_e || !want_grad) goto done;
    double err = scaled_error(clip_embedding(r), e, (size_t)B * A->output_dim);
    printf("%-30s e     error %.2e\n", formats[which].label, err);
    CHECK(err <= 1e-5, "%s: e differs from PyTorch by %.3g", formats[which].label, err);

    CHECK(clip_backward(r, d_hidden, NULL, d_e, d_images, &st) == WS_OK, "%s", st.msg);
    if (st.code) goto done;
    err = scaled_error(d_images, want_grad, image_n);
    printf("%-30s dL/dx error %.2e\n", formats[which].label, err);
    CHECK(err <= 1e-4, "%s: the input gradient differs from PyTorch by %.3g (relative to its largest value)",
          formats[which].label, err);
done:
    clip_run_free(r);
    clip_model_free(m);
    free(d_images);
}

/* P_l from a run with a tape and from one without (the photo's side of
 * the loss), and the input gradient of L = sum_l sum(P_l * D_l), the
 * probabilities' gradient alone (no h_l or e seeded). */
static void test_attention(const reference *ref, int which, const float *images) {
    const wf_arch *A = &ref->arch;
    const int B = ref->batch, T = 1 + (A->resolution / A->patch) * (A->resolution / A->patch);
    const size_t probs_n = (size_t)B * A->heads * T * T, image_n = (size_t)B * 3 * A->resolution * A->resolution;
    ws_status st;
    ws_status_clear(&st);
    clip_model *m = NULL;
    clip_run *r[2] = {NULL, NULL};
    float *d_images = malloc(image_n * sizeof *d_images);
    CHECK(clip_model_load(&m, paths[which], &st) == WS_OK, "%s", st.msg);
    for (int grad = 0; grad < 2 && m && !st.code; grad++) {
        clip_run_options opt = {B, A->layers - 1, 0, grad, 1};
        CHECK(clip_run_create(&r[grad], m, &opt, &st) == WS_OK, "%s", st.msg);
        if (r[grad]) CHECK(clip_forward(r[grad], images, &st) == WS_OK, "%s", st.msg);
    }
    if (!r[0] || !r[1] || st.code) goto done;
    const float *d_probs[MAX_LAYERS];
    for (int l = 0; l < A->layers; l++) {
        char name[32];
        snprintf(name, sizeof name, "attention_%d", l);
        const float *want = array(ref, name, probs_n);
        snprintf(name, sizeof name, "d_attention_%d", l);
        d_probs[l] = array(ref, name, probs_n);
        if (!want || !d_probs[l]) goto done;
        for (int grad = 0; grad < 2; grad++) {
            double err = scaled_error(clip_attention(r[grad], l), want, probs_n);
            printf("%-30s P_%d   error %.2e (%s tape)\n", formats[which].label, l, err, grad ? "with" : "without");
            CHECK(err <= 1e-5, "%s: P_%d (%s tape) differs from PyTorch by %.3g (relative to its largest value)",
                  formats[which].label, l, grad ? "with" : "without", err);
        }
    }
    const float *want_grad = array(ref, "d_images", image_n);
    if (!want_grad) goto done;
    CHECK(clip_backward(r[1], NULL, d_probs, NULL, d_images, &st) == WS_OK, "%s", st.msg);
    if (st.code) goto done;
    double err = scaled_error(d_images, want_grad, image_n);
    printf("%-30s dL/dx error %.2e (L from P_l)\n", formats[which].label, err);
    CHECK(err <= 1e-4, "%s: the input gradient through P_l differs from PyTorch by %.3g (relative to its largest value)",
          formats[which].label, err);
done:
    clip_run_free(r[0]);
    clip_run_free(r[1]);
    clip_model_free(m);
    free(d_images);
}

int main(void) {
    reference ref = {0}, att = {0};
    if (load_reference(&ref, "expected") || load_reference(&att, "attention")) return check_summary();
    dir = test_tmpdir("clip_fixture");
    CHECK(!memcmp(&att.arch, &ref.arch, sizeof att.arch) && att.batch == ref.batch,
          "attention.json and expected.json describe different models or batches");
    const size_t R = (size_t)ref.arch.resolution, image_n = (size_t)ref.batch * 3 * R * R;
    const float *images = array(&ref, "images", image_n);

    /* the reference images are the PNG's bytes / 255 (image 1 is image 0 mirrored) */
    ws_image png = {0};
    ws_status st;
    ws_status_clear(&st);
    CHECK(ws_image_read(FIXTURE "/image.png", 0, 0, (const float[3]){0, 0, 0}, &png, &st) == WS_OK, "%s", st.msg);
    if (images && st.code == WS_OK)
        CHECK(png.width == (int)R && png.height == (int)R && scaled_error(png.data, images, 3 * R * R) == 0,
              "image.png is not image 0 of expected.bin");
    ws_image_free(&png);

    if (images && convert_all()) {
        test_same_weights(&ref);
        for (int i = 0; i < FORMATS; i++) {
            test_model(&ref, i, images);
            test_attention(&att, i, images);
        }
    }
    cJSON_Delete(ref.json);
    free(ref.bin);
    cJSON_Delete(att.json);
    free(att.bin);
    return check_summary();
}
