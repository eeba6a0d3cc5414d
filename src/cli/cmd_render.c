/* cmd_render.c: `wiresketch render`: the stroke image of a sketch in every
 * view of a split, one 8-bit gray PNG per view: black strokes on white as
 * the fit's test renders (pixel = round(255 (1 - alpha))), or with --alpha
 * the stroke alpha itself (pixel = round(255 alpha)). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "base/paths.h"
#include "cli/cli_view.h"
#include "cli/commands.h"
#include "cli/args.h"
#include "cli/cli_rows.h"
#include "render/curves.h"
#include "io/image.h"
#include "base/outfile.h"
#include "render/splat.h"

/* Splats every view of `split` and writes OUT/<view name>.png. */
static int render_split(const ws_curves *curves, const ws_split *split, const char *out_dir,
                        const ws_splat_options *opt, int raw_alpha, ws_status *st) {
    ws_gaussians g = {0};
    ws_splat *splat = NULL;
    ws_image img = {0};
    double *alpha = NULL;
    int W = split->views[0].cam.width, H = split->views[0].cam.height;
    if (ws_curves_sample(curves, &g, st) || ws_splat_create(&splat, W, H, st) ||
        ws_image_alloc(&img, W, H, 1, st) ||
        !(alpha = ws_malloc((size_t)W * H * sizeof *alpha, "the stroke image", st)))
        goto done;
    for (int k = 0; k < split->n; k++) {
        const ws_view *v = &split->views[k];
        char path[WS_PATH_MAX];
        snprintf(path, sizeof path, "%s/%s.png", out_dir, v->name);
        if (ws_splat_forward(splat, &v->cam, g.mu, g.n, curves->thickness, opt, alpha, st))
            goto done;
        for (size_t p = 0; p < (size_t)W * H; p++) img.data[p] = (float)(raw_alpha ? alpha[p] : 1 - alpha[p]);
        if (ws_png_write(path, &img, st)) goto done;
    }
done:
    free(alpha);
    ws_image_free(&img);
    ws_splat_free(splat);
    ws_gaussians_free(&g);
    return st->code;
}

int cmd_render(int argc, char **argv) {
    const char *scene_dir = NULL, *split_name = "test", *out_dir = NULL;
    int size = 224, raw_alpha = 0;
    ws_splat_options opt;
    ws_splat_options_default(&opt);
    const ws_arg args[] = {
        {"--scene", WS_ARG_STRING, &scene_dir, 0, "scene directory (its cameras) [required]"},
        WS_ROW_SPLIT(&split_name),
        {"--out", WS_ARG_STRING, &out_dir, 0, "output directory, created if missing [required]"},
        WS_ROW_CUTOFF(&opt.cutoff),
        WS_ROW_SIZE(&size),
        {"--alpha", WS_ARG_FLAG, &raw_alpha, 0,
         "write the stroke alpha itself (white strokes on black) instead of black strokes on white"},
    };
    const ws_command_spec spec = {
        "render CURVES.json --scene DIR --out DIR [options]",
        "Splat a sketch into every view of a split: OUT/<view>.png, 8-bit gray, black strokes on white\n"
        "as the fit's test renders (--alpha: the alpha, white on black).",
        args, sizeof args / sizeof args[0], 1, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) return done;
    if (ws_cli_require(scene_dir, "--scene", &st) || ws_cli_require(out_dir, "--out", &st))
        return ws_cli_fail(&st);
    ws_curves curves = {0};
    ws_scene scene = {0};
    int split;
    if (!ws_outfile_protect(pos, 1, &scene_dir, 1, &st) && !ws_outfile_check(out_dir, &st) && !ws_curves_load(pos[0], &curves, &st) &&
        !ws_cli_load_split(scene_dir, size, 0, NULL, split_name, &scene, &split, &st)) {
        if (!ws_mkdir(out_dir, &st)) render_split(&curves, &scene.split[split], out_dir, &opt, raw_alpha, &st);
        ws_scene_free(&scene);
    }
    ws_curves_free(&curves);
    return st.code ? ws_cli_fail(&st) : 0;
}
