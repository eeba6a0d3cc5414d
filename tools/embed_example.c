/* embed_example.c: wiresketch used as a library, on data in memory.
 *
 * Usage: embed_example SCENE CURVES.json [CLIP.bin]
 * Loads a scene and a sketch, renders the sketch into the first test view
 * (or the first training view), and prints the loss against the photo and
 * the norm of its gradient with respect to the control points: the l2
 * loss, or with a CLIP weight file the CLIP fc term (1 - the cosine of
 * the sketch's and the photo's embeddings) on the scene loaded at the
 * model's resolution. It includes wiresketch.h alone.
 * Every call returns a status code and fills a ws_status with a one-line
 * message. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "wiresketch.h"

static int run(const char *scene_dir, const char *curves_path, const char *clip_path, ws_status *st) {
    ws_scene scene = {0};
    ws_curves curves = {0};
    ws_objective *obj = NULL;
    ws_clip_model *model = NULL;
    double *dP = NULL;
    ws_scene_options so;
    ws_scene_options_default(&so);
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    lo.conv_weight = lo.fc_weight = lo.global_weight = 0;
    lo.l2_weight = 1;
    ws_splat_options sp;
    ws_splat_options_default(&sp);
    int rc = clip_path ? ws_clip_model_load(&model, clip_path, st) : WS_OK;
    if (model) {
        /* one model, lent to the loss: a program with several objectives
         * lends them all the same one */
        lo.model = model;
        lo.n_layer_weights = 0; /* the geometric term is off; its default layer weights are for ViT-B/32 */
        lo.fc_weight = 1;
        lo.l2_weight = 0;
        so.width = so.height = ws_clip_model_resolution(model);
    }
    if (!rc) rc = ws_scene_load(&scene, scene_dir, &so, st);
    if (!rc) rc = ws_curves_load(curves_path, &curves, st);
    if (!rc) rc = ws_objective_create(&obj, &scene, &lo, &sp, curves.n, st);
    if (!rc && !(dP = ws_calloc((size_t)curves.n * WS_CURVE_FLOATS, sizeof *dP, "dP", st))) rc = st->code;
    int split = scene.split[WS_TEST].n ? WS_TEST : WS_TRAIN;
    double value = 0;
    if (!rc) rc = ws_objective_view(obj, &curves, split, 0, 0, NULL, 1.0, &value, dP, st);
    if (!rc) {
        double norm = 0;
        for (int i = 0; i < curves.n * WS_CURVE_FLOATS; i++) norm += dP[i] * dP[i];
        printf("view %s: %d curves, %d Gaussians, %s loss %.6g, |dL/dP| %.6g\n",
               scene.split[split].views[0].name, curves.n, ws_objective_gaussians(obj)->n, model ? "CLIP" : "l2",
               value, sqrt(norm));
    }
    free(dP);
    ws_objective_free(obj);
    ws_clip_model_free(model);
    ws_curves_free(&curves);
    ws_scene_free(&scene);
    return rc;
}

int main(int argc, char **argv) {
    if (argc != 3 && argc != 4) {
        fprintf(stderr, "usage: embed_example SCENE CURVES.json [CLIP.bin]\n");
        return 2;
    }
    /* as `wiresketch` does: OpenMP's idle threads sleep (a re-run with
     * OMP_WAIT_POLICY=passive), then threads and OpenBLAS's kernels */
    ws_runtime_reexec_if_needed(argv);
    ws_status st;
    ws_status_clear(&st);
    if (ws_runtime_init(0, &st) || run(argv[1], argv[2], argc == 4 ? argv[3] : NULL, &st)) {
        fprintf(stderr, "embed_example: %s\n", st.msg);
        return ws_exit_code(&st);
    }
    return 0;
}
