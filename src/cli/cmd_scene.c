/* cmd_scene.c: `wiresketch scene NAME --out DIR`: a synthetic test scene
 * (NeRF layout) with its ground-truth curves (see synth.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "base/progress.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "synth/smooth.h"
#include "synth/synth.h"

/* scene's text options into opt: --background, --size N or WxH,
 * --principal DX,DY, --layout and --lens k1,k2,p1,p2 (NULL: none). */
static int read_words(const char *background, const char *size, const char *principal, const char *layout,
                      const char *lens, ws_synth_options *opt, ws_status *st) {
    if (strcmp(background, "black") && strcmp(background, "white") && strcmp(background, "room") &&
        strcmp(background, "floor"))
        return ws_fail(st, WS_EUSAGE, "--background: '%s' is not black, white, room or floor", background);
    opt->white_background = !strcmp(background, "white");
    opt->on_floor = !strcmp(background, "floor");
    opt->room = opt->on_floor || !strcmp(background, "room");
    int w, h, used = 0;
    if (sscanf(size, "%dx%d%n", &w, &h, &used) == 2 && !size[used]) {
        opt->width = w;
        opt->height = h;
    } else if (sscanf(size, "%d%n", &opt->size, &used) != 1 || size[used]) {
        return ws_fail(st, WS_EUSAGE, "--size: '%s' is not N or WxH", size);
    }
    if (sscanf(principal, "%lf,%lf%n", &opt->principal[0], &opt->principal[1], &used) != 2 || principal[used] ||
        !isfinite(opt->principal[0]) || !isfinite(opt->principal[1]))
        return ws_fail(st, WS_EUSAGE, "--principal: '%s' is not DX,DY", principal);
    if (strcmp(layout, "nerf") && strcmp(layout, "nerfstudio") && strcmp(layout, "colmap") &&
        strcmp(layout, "colmap-text"))
        return ws_fail(st, WS_EUSAGE, "--layout: '%s' is not nerf, nerfstudio, colmap or colmap-text", layout);
    opt->nerfstudio = !strcmp(layout, "nerfstudio");
    opt->colmap = !strcmp(layout, "colmap") ? 1 : !strcmp(layout, "colmap-text") ? 2 : 0;
    used = 0;
    if (lens && (sscanf(lens, "%lf,%lf,%lf,%lf%n", &opt->lens[0], &opt->lens[1], &opt->lens[2],
                        &opt->lens[3], &used) != 4 ||
                 lens[used] != '\0' || !isfinite(opt->lens[0] + opt->lens[1] + opt->lens[2] + opt->lens[3])))
        return ws_fail(st, WS_EUSAGE, "--lens: '%s' is not k1,k2,p1,p2 (four numbers)", lens);
    return WS_OK;
}

int cmd_scene(int argc, char **argv) {
    ws_synth_options opt;
    ws_synth_options_default(&opt);
    const char *out = NULL, *background = "black", *layout = "nerf", *lens = NULL, *size = "224",
               *principal = "0,0";
    int seed = 0;
    const double default_fov = opt.angle * 180 / M_PI; /* in radians the default stays exact */
    double fov = default_fov;
    const ws_arg args[] = {
        {"--out", WS_ARG_STRING, &out, 0, "directory to write the scene into (required)"},
        {"--views-train", WS_ARG_INT, &opt.views[WS_TRAIN], 0, "train views [48]"},
        {"--views-val", WS_ARG_INT, &opt.views[WS_VAL], 0, "val views, 0 for none [8]"},
        {"--views-test", WS_ARG_INT, &opt.views[WS_TEST], 0, "test views, 0 for none [8]"},
        {"--size", WS_ARG_STRING, &size, 0, "image side N, or width x height WxH (nerfstudio and colmap layouts), pixels [224]"},
        {"--seed", WS_ARG_INT, &seed, 0, "seed of the camera placement [0]"},
        {"--background", WS_ARG_STRING, &background, 0,
         "black, white, room (a box room of patterned walls and floor far around the object) or floor (the same "
         "room, the object standing on its floor as on a table) [black]"},
        {"--masks", WS_ARG_FLAG, &opt.masks, 0, "also write masks/SPLIT/<image>.png (white = object) and, nerf and nerfstudio layouts, each frame's mask_path"},
        {"--principal", WS_ARG_STRING, &principal, 0,
         "the principal point DX, DY pixels right of and below the image centre, nerfstudio and colmap layouts [0,0]"},
        {"--layout", WS_ARG_STRING, &layout, 0,
         "nerf (transforms_SPLIT.json), nerfstudio (one transforms.json with intrinsics), colmap "
         "or colmap-text (images/, sparse/0/*.bin or *.txt with a noisy sparse cloud) [nerf]"},
        {"--lens", WS_ARG_STRING, &lens, 0,
         "k1,k2,p1,p2: the views seen through an OPENCV lens (nerfstudio, colmap) [none]"},
        {"--jpeg", WS_ARG_FLAG, &opt.jpeg, 0, "images as JPEG (quality 95), not PNG"},
        {"--width", WS_ARG_INT, &opt.width, 0, "image width, nerfstudio layout [--size]"},
        {"--height", WS_ARG_INT, &opt.height, 0, "image height, nerfstudio layout [--size]"},
        {"--fov", WS_ARG_DOUBLE, &fov, 0,
         "the field of view across the image's shorter side, degrees, in [10, 120]; wider: a smaller object in the "
         "frame [39.6]"},
    };
    const ws_command_spec spec = {
        "scene NAME --out DIR [options]   (NAME: trefoil, chair, spring, flat, cube, dodecahedron, nut, bracket, torus, vase, animal)",
        "Render a synthetic object into a NeRF-synthetic scene (or, with --layout, a\n"
        "nerfstudio or COLMAP capture, --lens and --jpeg as a camera takes it). Wire objects, drawn as\n"
        "shaded tubes along Bezier curves: trefoil (a knot), chair (a wire chair),\n"
        "spring (a coil of 5 turns, radius 0.3, 1 unit tall), flat (a paper clip lying\n"
        "in one tilted plane, seen edge-on by some views). Solids with sharp edges:\n"
        "cube, dodecahedron, nut, bracket (an L-shaped angle bracket: concave). Smooth\n"
        "textured objects, whose lines depend on the\n"
        "view: torus (striped), vase (spotted; two rims), animal (four legs, blotched).\n"
        "The scene:\n"
        "DIR/transforms_{train,val,test}.json, DIR/rgb/SPLIT/r_K.png, and its exact\n"
        "ground truth DIR/gt_curves.json (the tubes' curves, the solids' sharp edges;\n"
        "solids also DIR/gt_points.ply; none for the smooth objects), and in a\n"
        "NeRF-synthetic scene without --lens each test view's reference lines\n"
        "DIR/lines/test/r_K.png and r_K_parts.png (silhouette, inner contours,\n"
        "creases), which `eval` and `fit` score the drawing against.",
        args, sizeof args / sizeof args[0], 1, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) return done;
    if (!out) {
        ws_fail(&st, WS_EUSAGE, "--out: required (see --help)");
        return ws_cli_fail(&st);
    }
    if (seed < 0) {
        ws_fail(&st, WS_EUSAGE, "--seed: %d is negative", seed);
        return ws_cli_fail(&st);
    }
    if (!(fov >= 10 && fov <= 120)) {
        ws_fail(&st, WS_EUSAGE, "--fov: %g is not in [10, 120] degrees", fov);
        return ws_cli_fail(&st);
    }
    if (fov != default_fov) opt.angle = fov * M_PI / 180;
    if (read_words(background, size, principal, layout, lens, &opt, &st)) return ws_cli_fail(&st);
    opt.seed = (uint64_t)seed;
    ws_progress progress;
    ws_progress_init(&progress);
    opt.progress = &progress;
    if (ws_synth_write(pos[0], out, &opt, &st)) return ws_cli_fail(&st);
    printf("%s: %s scene, %d train / %d val / %d test views of %d x %d, %s %s/%s\n", out, pos[0],
           opt.views[WS_TRAIN], opt.views[WS_VAL], opt.views[WS_TEST], opt.width ? opt.width : opt.size,
           opt.height ? opt.height : opt.size, ws_smooth_exists(pos[0]) ? "reference lines" : "ground truth", out,
           ws_smooth_exists(pos[0]) ? "lines/test" : "gt_curves.json");
    return 0;
}
