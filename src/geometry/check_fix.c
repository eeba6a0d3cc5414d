/* check_fix.c: the corrected copy of a scene (ws_check_write_fixed, check.h). */
#include <cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/outfile.h"
#include "geometry/check.h"
#include "nn/base/bytes.h"

#define TRANSFORMS_MAX_BYTES ((size_t)64 << 20)

/* The focal lengths of one object (the file's root or a frame) scaled:
 * fl_x and fl_y times `scale`, camera_angle_x to the angle of that focal. */
static void scale_focal(cJSON *object, double scale) {
    static const char *const lengths[2] = {"fl_x", "fl_y"};
    for (int k = 0; k < 2; k++) {
        cJSON *fl = cJSON_GetObjectItemCaseSensitive(object, lengths[k]);
        if (cJSON_IsNumber(fl)) cJSON_SetNumberValue(fl, fl->valuedouble * scale);
    }
    cJSON *angle = cJSON_GetObjectItemCaseSensitive(object, "camera_angle_x");
    if (cJSON_IsNumber(angle)) cJSON_SetNumberValue(angle, 2 * atan(tan(0.5 * angle->valuedouble) / scale));
}

/* train/val/test_filenames naming the file_path of every frame kept
 * (drop[k] == 0) in its split (split_of[k]; -1: in none), in frame order. */
static int write_split_lists(cJSON *root, cJSON *frames, const int *split_of, const char *drop,
                             ws_status *st) {
    static const char *const keys[WS_NSPLITS] = {"train_filenames", "val_filenames", "test_filenames"};
    for (int s = 0; s < WS_NSPLITS; s++) {
        cJSON *list = cJSON_CreateArray();
        int k = 0, ok = list != NULL;
        for (cJSON *f = frames->child; f && ok; f = f->next, k++) {
            if (drop[k] || split_of[k] != s) continue;
            cJSON *name = cJSON_CreateString(cJSON_GetObjectItemCaseSensitive(f, "file_path")->valuestring);
            ok = name && cJSON_AddItemToArray(list, name);
        }
        if (ok)
            ok = cJSON_HasObjectItem(root, keys[s]) ? cJSON_ReplaceItemInObjectCaseSensitive(root, keys[s], list)
                                                    : cJSON_AddItemToObject(root, keys[s], list);
        if (!ok) {
            cJSON_Delete(list);
            return ws_fail(st, WS_ENOMEM, "out of memory for the split lists");
        }
    }
    return WS_OK;
}

/* Applies the fix of each frame's split to the parsed transforms `root`
 * (checked by the scene loader already: an object with frames whose
 * transform_matrix are 4x4 numbers): split_of[k], the split of frame k
 * (-1: in none, left as it is); drop[k], set for the bad frames. In file
 * order: frame k takes the camera listed for frame k + the split's
 * repair_shift (dropped where there is none), then the OpenCV flip of its
 * split, the focal scale of the file, and the drops. A nerfstudio file
 * (`lists`) that loses frames lists every split's frames explicitly, so
 * that the k % 8 rule does not move the frames after a dropped one. */
static int fix_frames(cJSON *root, const ws_check_report *r, const int *split_of, char *drop,
                      double focal_scale, int lists, ws_status *st) {
    cJSON *frames = cJSON_GetObjectItemCaseSensitive(root, "frames");
    const int n = cJSON_GetArraySize(frames);
    cJSON **moved = ws_calloc(n, sizeof *moved, "frames", st);
    if (!moved) return st->code;
    for (int k = 0; k < n; k++) {
        const int shift = split_of[k] < 0 ? 0 : r->split[split_of[k]].repair_shift, c = k + shift;
        if (!shift) continue;
        if (c < 0 || c >= n)
            drop[k] = 1;
        else
            moved[k] = cJSON_Duplicate(
                cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(frames, c), "transform_matrix"), 1);
    }
    int k = 0, dropped = 0;
    for (cJSON *f = frames->child; f; f = f->next, k++) {
        if (moved[k]) cJSON_ReplaceItemInObjectCaseSensitive(f, "transform_matrix", moved[k]);
        if (split_of[k] >= 0 && r->split[split_of[k]].cause == WS_CAUSE_OPENCV) {
            cJSON *m = cJSON_GetObjectItemCaseSensitive(f, "transform_matrix");
            for (int i = 0; i < 3; i++)
                for (int j = 1; j <= 2; j++) {
                    cJSON *e = cJSON_GetArrayItem(cJSON_GetArrayItem(m, i), j);
                    cJSON_SetNumberValue(e, -e->valuedouble);
                }
        }
        if (focal_scale != 1) scale_focal(f, focal_scale);
        dropped += drop[k];
    }
    free(moved);
    if (focal_scale != 1) scale_focal(root, focal_scale);
    if (lists && dropped && write_split_lists(root, frames, split_of, drop, st)) return st->code;
    for (k = n - 1; k >= 0; k--)
        if (drop[k]) cJSON_DeleteItemFromArray(frames, k);
    return WS_OK;
}

/* Rewrites the file that holds the splits `first` .. `last` with their
 * fixes. */
static int write_file(const ws_scene *scene, const ws_check_report *r, int first, int last, const char *out,
                      ws_status *st) {
    const char *file = ws_scene_file(scene, first);
    char in_path[WS_PATH_MAX], out_path[WS_PATH_MAX];
    snprintf(in_path, sizeof in_path, "%s/%s", scene->dir, file);
    snprintf(out_path, sizeof out_path, "%s/%s", out, file);
    unsigned char *bytes = NULL;
    size_t length = 0;
    if (ws_read_file(in_path, TRANSFORMS_MAX_BYTES, &bytes, &length, st)) return st->code;
    cJSON *root = cJSON_ParseWithLength((const char *)bytes, length);
    free(bytes);
    const int n = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "frames"));
    int *split_of = root ? ws_malloc(sizeof *split_of * (n ? n : 1), "frames", st) : NULL;
    char *drop = split_of ? ws_calloc(n ? n : 1, 1, "frames", st) : NULL;
    int rc = !root ? ws_fail(st, WS_EINPUT, "%s: changed while it was checked", in_path) : drop ? WS_OK : st->code;
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
    char *text = NULL;
    if (!rc) rc = fix_frames(root, r, split_of, drop, focal_scale, scene->layout == WS_LAYOUT_NERFSTUDIO, st);
    if (!rc && !(text = cJSON_Print(root))) rc = ws_fail(st, WS_ENOMEM, "out of memory for %s", out_path);
    cJSON_Delete(root);
    free(split_of);
    free(drop);
    ws_outfile f;
    if (!rc && !(rc = ws_outfile_open(&f, out_path, st))) {
        fputs(text, f.fp);
        fputc('\n', f.fp);
        rc = ws_outfile_commit(&f, st);
    }
    free(text);
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
        if (e->d_name[0] == '.' || !strncmp(e->d_name, "transforms_", 11) ||
            (nerfstudio && !strcmp(e->d_name, "transforms.json")))
            continue;
        char target[PATH_MAX + 256], link[4400];
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
