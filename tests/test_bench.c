/* slow test */
/* test_bench.c: the augmentation bank (its cache changes no bit, a resumed
 * fit with a bank ends bit-identical, bad sizes are refused), the step's
 * timers (they change no bit and account for the step), and the
 * measurements of `wiresketch bench` on a small scene and a small random
 * CLIP of the real architecture: errors that shrink as they must, zero
 * errors where the approximation is exact, and the command's JSON (of its
 * quickest part, CLIP at batch 1). */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include "bench/bench.h"
#include "check.h"
#include "test_util.h"
#include "synth/synth.h"
#include "base/runtime.h"
#include "nn/clip.h"
#include "nn/gemm_bf16.h"
#include "wiresketch.h"
#include "scene_load.h"

static const char *tmp;

/* A 6-block ViT at 64 x 64 (17 tokens of width 64): blocks 2 and 3 of the
 * default loss exist, and a step takes milliseconds. */
static const wf_arch small_arch = {64, 6, 4, 16, 64, 32};

/* The loss and gradient of one training step on view 0 from rng state rng0. */
static double step_loss(ws_objective *s, const ws_curves *c, const ws_rng *rng0, double *grad) {
    ws_status st = {0};
    ws_rng rng = *rng0;
    double loss = NAN;
    const int view = 0;
    if (ws_objective_batch(s, c, &view, 1, &rng, &loss, grad, &st)) fprintf(stderr, "step: %s\n", st.msg);
    return loss;
}

static ws_loss_options options(const clip_model *m, int bank, uint64_t seed) {
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    lo.model = m;
    lo.aug_bank = bank;
    lo.aug_seed = seed;
    return lo;
}

static void test_bank_and_timing(const ws_scene *scene, const clip_model *m, const ws_curves *c) {
    ws_status st = {0};
    ws_splat_options so;
    ws_splat_options_default(&so);
    ws_loss *loss = NULL;
    ws_loss_options bad = options(m, 2, 0);
    CHECK(ws_loss_create(&loss, &bad, scene, &st) == WS_EUSAGE &&
              !strcmp(st.msg, "--aug-bank: 2 is not 0 or in 4..4096 (a step uses --num-aug 4 distinct "
                              "transforms of the bank)"),
          "a bank smaller than --num-aug: %s", st.msg);
    ws_loss_free(loss);

    size_t bytes = (size_t)c->n * WS_CURVE_FLOATS * sizeof(double);
    double *g[4];
    for (int k = 0; k < 4; k++) g[k] = malloc(bytes);
    ws_objective *s[3] = {NULL, NULL, NULL};
    ws_loss_options lo[3] = {options(m, 6, 5), options(m, 6, 5), options(m, 6, 6)};
    for (int k = 0; k < 3; k++)
        CHECK(ws_objective_create(&s[k], scene, &lo[k], &so, c->n, &st) == WS_OK, "step: %s", st.msg);
    ws_rng rng0;
    ws_rng_seed(&rng0, 8);
    /* the first step fills view 0's bank, the second reads it */
    double cold = step_loss(s[0], c, &rng0, g[0]), warm = step_loss(s[0], c, &rng0, g[1]);
    CHECK(isfinite(cold) && cold == warm && !memcmp(g[0], g[1], bytes),
          "a banked step from its cache differs from the step that filled it: %.17g %.17g", cold, warm);
    double again = step_loss(s[1], c, &rng0, g[2]), other = step_loss(s[2], c, &rng0, g[3]);
    CHECK(again == cold && !memcmp(g[2], g[0], bytes), "the same bank seed gave another step");
    CHECK(other != cold, "another bank seed gave the same loss %.17g", other);
    size_t features = 2 * 17 * 64 + 32; /* blocks 2 and 3, and the embedding */
    CHECK(ws_loss_bank_bytes(ws_objective_loss(s[0])) == (size_t)scene->split[WS_TRAIN].n * 6 * features * sizeof(float),
          "bank of %zu bytes", ws_loss_bank_bytes(ws_objective_loss(s[0])));
    /* another rng state draws other transforms of the bank */
    ws_rng rng1;
    ws_rng_seed(&rng1, 9);
    CHECK(step_loss(s[0], c, &rng1, g[3]) != cold, "another rng state picked the same transforms");

    /* timers change no bit and account for the step */
    ws_step_timing t;
    memset(&t, 0, sizeof t);
    ws_objective_set_timing(s[0], &t);
    double t0 = ws_seconds(), timed = step_loss(s[0], c, &rng0, g[3]), total = ws_seconds() - t0;
    ws_objective_set_timing(s[0], NULL);
    CHECK(timed == cold && !memcmp(g[3], g[0], bytes), "timing changed the step");
    double parts = 0;
    for (int k = 0; k < WS_TIME_TOTAL; k++) parts += t.seconds[k];
    CHECK(t.seconds[WS_TIME_SPLAT] > 0 && t.seconds[WS_TIME_AUGMENT] > 0 &&
              t.seconds[WS_TIME_CLIP_FORWARD] > 0 && t.seconds[WS_TIME_CLIP_BACKWARD] > 0 &&
              t.seconds[WS_TIME_CLIP_PHOTO] == 0 && parts <= total,
          "timed parts: splat %g augment %g forward %g photo %g backward %g, sum %g of %g",
          t.seconds[WS_TIME_SPLAT], t.seconds[WS_TIME_AUGMENT], t.seconds[WS_TIME_CLIP_FORWARD],
          t.seconds[WS_TIME_CLIP_PHOTO], t.seconds[WS_TIME_CLIP_BACKWARD], parts, total);
    for (int k = 0; k < 3; k++) ws_objective_free(s[k]);
    for (int k = 0; k < 4; k++) free(g[k]);
}

static void test_splat_measure(const ws_scene *scene) {
    ws_status st = {0};
    ws_bench_splat_row r;
    const ws_camera *cam = &scene->split[WS_TRAIN].views[0].cam;
    CHECK(ws_bench_splat(cam, scene->center, 500, 1, &r, &st) == WS_OK, "splat bench: %s", st.msg);
    int ex = WS_BENCH_CUTOFFS - 1;
    CHECK(r.alpha_max[ex] == 0 && r.grad_max[ex] == 0, "the exact sum has an error against itself");
    for (int k = 1; k < ex; k++)
        CHECK(r.alpha_max[k] < r.alpha_max[k - 1] && r.grad_mean[k] < r.grad_mean[k - 1] &&
                  r.pixel_visits[k] > r.pixel_visits[k - 1],
              "cut-off %g: error or visits not monotonic", ws_bench_cutoffs[k]);
    CHECK(r.alpha_max[3] < 1e-3 && r.grad_mean[2] < 3e-2, "4 and 5 sigma errors %g %g", r.grad_mean[2],
          r.alpha_max[3]);
    CHECK(r.pixel_visits[ex] == 500.0 * 64 * 64, "exact visits %g", r.pixel_visits[ex]);
}

/* bench bank: a bank against itself differs by nothing, against another
 * bank or fresh transforms by something; the bias never exceeds the
 * difference it is taken from; too few steps are refused. */
static void test_bank_bias(const ws_scene *scene, const clip_model *m, const ws_curves *c) {
    ws_status st = {0};
    ws_bench_bank_row rows[] = {{.bank = 4, .aug_seed = 5, .against = -1},
                                {.bank = 4, .aug_seed = 6, .against = 0},
                                {.bank = 4, .aug_seed = 5, .against = 0}};
    ws_bench_bank_input in = {scene, m, c, 4};
    CHECK(ws_bench_bank(&in, rows, 3, &st) == WS_OK, "bank bench: %s", st.msg);
    for (int r = 0; r < 3; r++)
        CHECK(isfinite(rows[r].difference) && rows[r].bias <= rows[r].difference && rows[r].difference_noise >= 0 &&
                  rows[r].fresh_step_noise > 0 && rows[r].num_aug == 4 && rows[r].steps == 4,
              "bank row %d: difference %g, bias %g, noise %g, step noise %g", r, rows[r].difference, rows[r].bias,
              rows[r].difference_noise, rows[r].fresh_step_noise);
    /* a bank of A transforms gives every step all A of them, so only the
     * fresh transforms' steps vary: the noise of rows 1 and 2, banks
     * against a bank, is rounding at most, 0 on some machines */
    CHECK(rows[0].difference_noise > 0, "fresh transforms against a bank: no noise");
    CHECK(rows[0].difference > 0 && rows[1].difference > 0, "a bank equal to fresh transforms or to another bank");
    CHECK(rows[2].difference == 0 && rows[2].bias == 0 && rows[2].loss_difference == 0,
          "a bank against itself: %g", rows[2].difference);
    CHECK(fabs(rows[0].predicted - rows[0].fresh_step_noise) < 1e-12 * rows[0].predicted &&
              fabs(rows[1].predicted - sqrt(2.0) * rows[1].fresh_step_noise) < 1e-12 * rows[1].predicted,
          "predicted %g %g for step noise %g", rows[0].predicted, rows[1].predicted, rows[0].fresh_step_noise);
    in.steps = 1;
    CHECK(ws_bench_bank(&in, rows, 1, &st) == WS_EUSAGE && !strcmp(st.msg, "bench bank: 1 steps, at least 2 needed"),
          "one step: %s", st.msg);
}

/* m16: m's weights with bf16 GEMMs, or NULL on a CPU without AVX512_BF16
 * (then the approx table has no bf16 rows). */
static void test_step_and_approx(const ws_scene *scene, const clip_model *m, const clip_model *m16,
                                 const ws_curves *c) {
    ws_status st = {0};
    ws_bench_step_result r;
    CHECK(ws_bench_step(scene, m, c, 1, &r, &st) == WS_OK, "step bench: %s", st.msg);
    double parts = 0;
    for (int k = 0; k < WS_TIME_TOTAL; k++) parts += r.best.seconds[k];
    CHECK(r.floor > 0 && r.gaussians > 100 && parts <= r.best.seconds[WS_TIME_TOTAL] && parts > 0,
          "step: floor %g, %d Gaussians, parts %g of %g", r.floor, r.gaussians, parts,
          r.best.seconds[WS_TIME_TOTAL]);

    ws_bench_approx_row rows[32];
    int n = 0;
    ws_bench_approx_input in = {scene, m, NULL, NULL, c, 1, 4, m16};
    CHECK(ws_bench_approx(&in, rows, 32, &n, &st) == WS_OK, "approx bench: %s", st.msg);
    static const char *const names[] = {"cutoff", "cutoff", "cutoff", "cutoff", "culling", "clip_stop",
                                        "photo_cache", "aug_bank", "threads", "num_aug", "num_aug", "num_aug"};
    int extra = m16 ? 2 : 0; /* the bf16 rows, after aug_bank */
    CHECK(n == 12 + extra, "%d rows", n);
    for (int i = 0; i < n && i < 12 + extra; i++) {
        const char *name = i < 8 ? names[i] : i < 8 + extra ? (i == 8 ? "bf16" : "aug_seed") : names[i - extra];
        CHECK(!strcmp(rows[i].name, name), "row %d is %s, expected %s", i, rows[i].name, name);
    }
    if (n != 12 + extra) return;
    if (m16) {
        /* bf16 changes the step a little; other augmentations move it more */
        CHECK(rows[8].grad_error > 0 && rows[8].grad_error < rows[9].grad_error && rows[9].loss_error > 0,
              "bf16: gradient error %g, other augmentations %g", rows[8].grad_error, rows[9].grad_error);
        memmove(&rows[8], &rows[10], (size_t)(n - 10) * sizeof rows[0]);
    }
    for (int k = 1; k < 4; k++)
        CHECK(rows[k].grad_error < rows[k - 1].grad_error && rows[k].loss_error < rows[k - 1].loss_error,
              "cut-off rows: errors not falling");
    CHECK(rows[3].grad_error < 1e-3, "5 sigma: gradient error %g", rows[3].grad_error);
    /* stopping after the last block read and caching change nothing */
    CHECK(rows[5].loss_error == 0 && rows[5].grad_error == 0, "stopping CLIP early: %g %g",
          rows[5].loss_error, rows[5].grad_error);
    CHECK(rows[6].loss_error == 0 && rows[6].grad_error == 0, "the photo cache: %g %g", rows[6].loss_error,
          rows[6].grad_error);
    CHECK(rows[7].bytes > 0 && isnan(rows[7].loss_error), "the bank row");
    CHECK(rows[8].grad_error == 0 && rows[8].loss_error == 0, "threads: errors %g %g (not the same bits)",
          rows[8].loss_error, rows[8].grad_error);
    for (int i = 0; i < n; i++)
        CHECK(rows[i].step_exact > 0 && rows[i].step_approx > 0 && rows[i].part_exact >= 0,
              "row %d (%s) has no times", i, rows[i].name);
}

/* fit --aug-bank: a resumed run ends bit-identical; the bank is used. */
static void test_fit_with_bank(void) {
    char args[2048], weights[300], a[300], b[300];
    snprintf(weights, sizeof weights, "%s/tiny.bin", tmp);
    snprintf(args, sizeof args,
             "python3 tools/convert_weights.py tests/fixtures/clip_tiny/clip_tiny_state_dict.pt %s >/dev/null",
             weights);
    CHECK(system(args) == 0, "converting the tiny model failed");
#define FIT_BANK "fit %s/scene --size 64 --weights %s --clip-conv-layer-weights 1 1 --length 0.3 " \
                 "--inner-steps 3 --threads 1 --seed 3 --quiet --eval-every 0"
    const char *const variants[] = {"--aug-bank 5 --max-steps 6", "--aug-bank 5 --max-steps 3",
                                    "--max-steps 6"};
    const char *const dirs[] = {"bank", "bank_resumed", "fresh"};
    for (int k = 0; k < 3; k++) {
        snprintf(args, sizeof args, FIT_BANK " --out %s/%s %s", tmp, weights, tmp, dirs[k], variants[k]);
        CHECK(run("%s", args) == 0, "fit %s failed", dirs[k]);
    }
    snprintf(args, sizeof args, "fit --resume %s/bank_resumed --max-steps 6", tmp);
    CHECK(run("%s", args) == 0, "resume failed");
    snprintf(a, sizeof a, "%s/bank/curves.json", tmp);
    snprintf(b, sizeof b, "%s/bank_resumed/curves.json", tmp);
    CHECK(same_file(a, b), "a resumed fit with an augmentation bank differs from an uninterrupted one");
    snprintf(b, sizeof b, "%s/fresh/curves.json", tmp);
    CHECK(!same_file(a, b), "the bank made no difference");
    snprintf(args, sizeof args, FIT_BANK " --out %s/bad --aug-bank 3", tmp, weights, tmp);
    CHECK(run("%s", args) == 2 && strstr(run_stderr(), "--aug-bank: 3 is not 0 or in 4..4096"),
          "bad --aug-bank: %s", run_stderr());
}

static void test_command(void) {
    CHECK(run("bench nope") == 2 && strstr(run_stderr(), "bench nope: unknown part"), "unknown part: %s",
          run_stderr());
    CHECK(run("bench --help") == 0, "bench --help");
    CHECK(run("bench clip --json --rounds 1 --batch 1") == 0, "bench clip --json failed: %s", run_stderr());
    cJSON *j = cJSON_Parse(run_stdout());
    cJSON *clip = cJSON_GetObjectItem(j, "clip"), *machine = cJSON_GetObjectItem(j, "machine");
    CHECK(cJSON_IsString(cJSON_GetObjectItem(machine, "kernels")), "no machine description");
    static const char *const keys[] = {"forward", "forward_backward", "floor_forward",
                                       "floor_forward_backward", "ratio_forward_backward",
                                       "floor_forward_backward_openblas"};
    for (int k = 0; k < 6; k++) {
        cJSON *x = cJSON_GetObjectItem(clip, keys[k]);
        CHECK(cJSON_IsNumber(x) && x->valuedouble > 0, "clip.%s missing", keys[k]);
    }
    cJSON *matmul = cJSON_GetObjectItem(cJSON_GetObjectItem(clip, "ops"), "matmul");
    CHECK(cJSON_IsNumber(cJSON_GetObjectItem(matmul, "forward")) &&
              cJSON_GetObjectItem(matmul, "forward")->valuedouble > 0,
          "clip.ops.matmul.forward missing");
    /* --precision auto: the bf16 rows where the CPU has AVX512_BF16, against the same fp32 floor */
    cJSON *bf16 = cJSON_GetObjectItem(cJSON_GetObjectItem(clip, "bf16"), "ratio_forward_backward");
    CHECK(nn_bf16_available() ? cJSON_IsNumber(bf16) && bf16->valuedouble > 0 : !bf16,
          "clip.bf16: %s where the CPU %s AVX512_BF16", bf16 ? "present" : "missing",
          nn_bf16_available() ? "has" : "lacks");
    CHECK(cJSON_GetArraySize(j) == 2, "bench clip printed more than the machine and its part");
    cJSON_Delete(j);
}

int main(void) {
    tmp = test_tmpdir("bench");
    /* one thread: this process cannot make OpenMP's idle threads sleep
     * (OMP_WAIT_POLICY is read before main), and spinning ones would take
     * most of the time of the many small steps below */
    ws_status st = {0};
    CHECK(ws_runtime_init(1, &st) == WS_OK, "runtime: %s", st.msg);
    char dir[300];
    snprintf(dir, sizeof dir, "%s/scene", tmp);
    ws_synth_options syn;
    synth_options_at(&syn, 64, 6, 0, 1);
    ws_scene scene;
    clip_model *m = NULL;
    ws_curves c = {0};
    int rc = ws_synth_write("trefoil", dir, &syn, &st);
    if (!rc) rc = load_scene_at(&scene, dir, 64, &st);
    if (!rc) rc = clip_model_random(&m, &small_arch, 2, &st);
    if (!rc) rc = ws_bench_sketch(&c, 8, scene.center, 0.5, 1.0, 1, &st);
    CHECK(rc == WS_OK, "setup: %s", st.msg);
    if (rc) return check_summary();
    test_bank_and_timing(&scene, m, &c);
    test_splat_measure(&scene);
    test_bank_bias(&scene, m, &c);
    clip_model *m16 = NULL;
    if (nn_bf16_available()) {
        CHECK(clip_model_random(&m16, &small_arch, 2, &st) == WS_OK &&
                  clip_model_set_precision(m16, CLIP_BF16, &st) == WS_OK,
              "bf16 model: %s", st.msg);
    }
    test_step_and_approx(&scene, m, m16, &c);
    clip_model_free(m16);
    test_fit_with_bank();
    test_command();
    ws_curves_free(&c);
    clip_model_free(m);
    ws_scene_free(&scene);
    return check_summary();
}
