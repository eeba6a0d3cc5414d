/* cmd_export.c: `wiresketch export`: a sketch as OBJ, PLY and SVG files. */
#include <stdio.h>
#include <string.h>
#include "cli/args.h"
#include "cli/cli_rows.h"
#include "cli/cli_view.h"
#include "cli/commands.h"
#include "render/curves.h"
#include "io/export.h"
#include "base/outfile.h"
#include "cli/cli_loss.h"
#include "objective/hidden_lines.h"
#include "objective/line_evidence.h"
#include <stdlib.h>

/* The drawing's layers of a view (objective/line_evidence.h) into
 * layers (2 x H x W: lines, keep); 0 in *have when the training views'
 * silhouettes carve no hull (warned: the SVG is the curves alone, as a
 * fit's renders are then). */
static int drawing_layers(const ws_scene *scene, const ws_camera *cam, uint8_t **layers, int *have, ws_status *st) {
    ws_drawing_hull dh;
    *have = 0;
    int rc = ws_drawing_hull_make(&dh, scene, st);
    if (rc == WS_EINPUT) {
        fprintf(stderr, "wiresketch: warning: %s; the SVG is the curves alone\n", st->msg);
        ws_status_clear(st);
        return WS_OK;
    }
    if (rc) return rc;
    const size_t n = (size_t)cam->width * cam->height;
    *layers = ws_malloc(2 * n, "the drawing's layers", st);
    if (*layers && !ws_drawing_hull_layers(&dh, cam, *layers, *layers + n, st)) *have = 1;
    ws_drawing_hull_free(&dh);
    return st->code;
}

/* The SVG of the sketch seen from view `view` of a split of the scene;
 * with hidden lines removed, by the training views' visual hull as the
 * fit's stroke images are (objective/hidden_lines.h); with drawing, the
 * drawing a user gets (the curves where it keeps them and the hull's
 * lines). */
static int export_svg(const char *path, const ws_curves *curves, const char *scene_dir, const char *split_name,
                      int view, int size, int hidden, int drawing, const char *background, ws_status *st) {
    ws_scene scene;
    int split;
    if (ws_cli_load_split(scene_dir, size, hidden || drawing, background, split_name, &scene, &split, st))
        return st->code;
    ws_view_targets *targets = NULL;
    ws_hidden_lines *hl = NULL;
    const float *far = NULL;
    uint8_t *layers = NULL;
    int have = 0;
    const ws_camera *cam = &scene.split[split].views[view].cam;
    const size_t n = (size_t)scene.width * scene.height;
    if (!ws_cli_check_view(&scene, split, view, st) &&
        (!hidden || (!ws_view_targets_create(&targets, &scene, st) &&
                     !ws_hidden_lines_create(&hl, &scene, NULL, targets, st) &&
                     !ws_hidden_lines_far(hl, split, view, &far, st))) &&
        (!drawing || !drawing_layers(&scene, cam, &layers, &have, st))) {
        ws_svg_drawing layered = {.keep = have ? layers + n : NULL, .lines = layers};
        ws_export_svg(path, curves, cam, far, have ? &layered : NULL, st);
    }
    free(layers);
    ws_hidden_lines_free(hl);
    ws_view_targets_free(targets);
    ws_scene_free(&scene);
    return st->code;
}

int cmd_export(int argc, char **argv) {
    const char *obj = NULL, *ply = NULL, *svg = NULL, *scene_dir = NULL, *split_name = "test";
    const char *hidden = "none", *background = "black", *drawing = "hull";
    int view = 0, size = 224;
    const ws_arg args[] = {
        {"--obj", WS_ARG_STRING, &obj, 0, "write the curves as OBJ polylines, one object per curve"},
        {"--ply", WS_ARG_STRING, &ply, 0, "write the curves as a PLY of vertices and edges"},
        {"--svg", WS_ARG_STRING, &svg, 0, "write the sketch seen from a view as SVG, a path of cubic Beziers per curve"},
        {"--scene", WS_ARG_STRING, &scene_dir, 0, "scene directory, for --svg's camera"},
        WS_ROW_SPLIT(&split_name),
        WS_ROW_VIEW(&view),
        WS_ROW_SIZE(&size),
        {"--hidden-lines", WS_ARG_STRING, &hidden, 0,
         "--svg: hull (leave out what the training views' visual hull, made on --background, hides, as a fit "
         "with hidden lines draws) or none [none]"},
        {"--drawing", WS_ARG_STRING, &drawing, 0,
         "--svg: hull (the drawing a fit's renders show: the curves where the training views' visual hull "
         "supports a line, and the hull's outline and contours in that view) or curves (the curves alone) [hull]"},
        WS_ROW_BACKGROUND(&background),
    };
    const ws_command_spec spec = {
        "export CURVES.json [--obj FILE] [--ply FILE] [--svg FILE --scene DIR [--split S --view K] [--drawing MODE]]",
        "Write a sketch as OBJ or PLY polylines, or as an SVG drawing of Bezier paths from one camera.",
        args, sizeof args / sizeof args[0], 1, 1, NULL, 0};
    const char *pos[1];
    ws_status st;
    int npos, done = ws_cli_parse(&spec, argc, argv, pos, &npos, &st);
    if (done != WS_CLI_GO_ON) return done;
    if (!obj && !ply && !svg) {
        ws_fail(&st, WS_EUSAGE, "nothing to do: give --obj, --ply or --svg (see --help)");
        return ws_cli_fail(&st);
    }
    if (svg && ws_cli_require(scene_dir, "--scene", &st)) return ws_cli_fail(&st);
    ws_hidden_mode mode;
    if (ws_cli_hidden_mode(hidden, &mode, &st)) return ws_cli_fail(&st);
    if (strcmp(drawing, "hull") && strcmp(drawing, "curves")) {
        ws_fail(&st, WS_EUSAGE, "--drawing: '%s' is not hull or curves", drawing);
        return ws_cli_fail(&st);
    }
    ws_curves curves;
    const char *folders[] = {svg ? scene_dir : NULL};
    if (ws_outfile_protect(pos, 1, folders, 1, &st) || ws_curves_load(pos[0], &curves, &st)) return ws_cli_fail(&st);
    if (!(obj && ws_export_obj(obj, &curves, &st)) && !(ply && ws_export_ply(ply, &curves, &st)))
        if (svg)
            export_svg(svg, &curves, scene_dir, split_name, view, size, mode == WS_HIDDEN_HULL,
                       !strcmp(drawing, "hull"), background, &st);
    ws_curves_free(&curves);
    return st.code ? ws_cli_fail(&st) : 0;
}
