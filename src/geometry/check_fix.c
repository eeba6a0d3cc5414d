/* check_fix.c: the corrected copy of a scene (ws_check_write_fixed, check.h). */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/outfile.h"
#include "base/paths.h"
#include "geometry/check.h"
#include "io/transforms.h"

/* Rewrites the file that holds the splits `first` .. `last` with their
 * fixes (io/transforms.h), in file order: frame k takes the camera listed
 * for frame k + its split's repair_shift (dropped where there is none),
 * then the OpenCV flip of its split, the focal scale of the file, and the
 * drops of bad frames. */
static int write_file(const ws_scene *scene, const ws_check_report *r, int first, int last, const char *out,
                      ws_status *st) {
    const char *file = ws_scene_file(scene, first);
    char in_path[WS_PATH_MAX], out_path[WS_PATH_MAX];
    snprintf(in_path, sizeof in_path, "%s/%s", scene->dir, file);
    snprintf(out_path, sizeof out_path, "%s/%s", out, file);
    ws_transforms *t;
    const int kind = scene->layout == WS_LAYOUT_NERFSTUDIO ? WS_TRANSFORMS_NERFSTUDIO : WS_TRANSFORMS_SPLIT;
    if (ws_transforms_open(&t, in_path, kind, st)) return st->code;
    const int n = ws_transforms_count(t);
    int *split_of = ws_malloc(sizeof *split_of * n, "frames", st);
    int *camera = split_of ? ws_malloc(sizeof *camera * n, "frames", st) : NULL;
    char *drop = camera ? ws_calloc(n, 1, "frames", st) : NULL;
    char *flip = drop ? ws_calloc(n, 1, "frames", st) : NULL;
    int rc = flip ? WS_OK : st->code;
    /* the focal of the split this file holds, or of the split the line
     * explains where the file holds every split (one focal serves them) */
    const int named = first == last ? first : r->explained;
    const double focal_scale =
        named >= 0 && r->split[named].cause == WS_CAUSE_FOCAL ? r->split[named].focal_scale : 1;
    for (int k = 0; k < n && !rc; k++) split_of[k] = -1;
    for (int s = first; s <= last && !rc; s++) {
        const ws_check_split *c = &r->split[s];
        for (int k = 0; k < scene->split[s].n && !rc; k++) {
            const int frame = scene->split[s].views[k].frame;
            if (frame < n)
                split_of[frame] = s;
            else
                rc = ws_fail(st, WS_EINPUT, "%s: changed while it was checked", in_path);
        }
        for (int d = 0; d < c->ndisagree && !rc && c->cause == WS_CAUSE_BAD_FRAMES; d++)
            drop[scene->split[s].views[c->disagree[d]].frame] = 1;
    }
    for (int k = 0; k < n && !rc; k++) {
        const int shift = split_of[k] < 0 ? 0 : r->split[split_of[k]].repair_shift, c = k + shift;
        camera[k] = c < 0 || c >= n ? k : c;
        drop[k] |= c < 0 || c >= n;
        flip[k] = split_of[k] >= 0 && r->split[split_of[k]].cause == WS_CAUSE_OPENCV;
    }
    const ws_transforms_edit edit = {camera, flip, drop, focal_scale, split_of};
    if (!rc) rc = ws_transforms_rewrite(t, &edit, out_path, st);
    ws_transforms_close(t);
    free(split_of);
    free(camera);
    free(drop);
    free(flip);
    return rc;
}

/* Links every entry of the scene directory but its transforms files
 * (transforms_*.json, and for a nerfstudio scene transforms.json). */
static int link_rest(const char *dir, int nerfstudio, const char *out, ws_status *st) {
    char real[PATH_MAX];
    if (!realpath(dir, real)) return ws_fail(st, WS_EIO, "%s: %s", dir, strerror(errno));
    DIR *d = opendir(real);
    if (!d) return ws_fail(st, WS_EIO, "%s: %s", dir, strerror(errno));
    int rc = WS_OK;
    for (struct dirent *e; !rc && (e = readdir(d));) {
        if (e->d_name[0] == '.' || ws_transforms_is_file(e->d_name, nerfstudio)) continue;
        char target[PATH_MAX + 256], link[WS_PATH_MAX];
        snprintf(target, sizeof target, "%s/%s", real, e->d_name);
        snprintf(link, sizeof link, "%s/%s", out, e->d_name);
        if (symlink(target, link) && errno != EEXIST)
            rc = ws_fail(st, WS_EIO, "%s: cannot link: %s", link, strerror(errno));
    }
    closedir(d);
    return rc;
}

int ws_check_write_fixed(const ws_scene *scene, const ws_check_report *r, const char *out,
                         ws_status *st) {
    /* the caller protects the scene (base/outfile.h): a copy inside it would link to itself */
    if (ws_mkdir(out, st)) return st->code;
    const int nerfstudio = scene->layout == WS_LAYOUT_NERFSTUDIO;
    if (nerfstudio && write_file(scene, r, 0, WS_NSPLITS - 1, out, st)) return st->code;
    for (int s = 0; s < WS_NSPLITS && !nerfstudio; s++)
        if (r->split[s].n > 0 && write_file(scene, r, s, s, out, st)) return st->code;
    return link_rest(scene->dir, nerfstudio, out, st);
}
