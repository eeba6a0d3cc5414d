/* check.h: does every view's photo agree with its camera?
 *
 * A view's agreement is the share of its silhouette covered by the
 * projection of the visual hull carved from the other views of its split
 * (hull.h). In a consistent split every view agrees (a hull is never
 * smaller than the object, so a right view is covered up to the slack). A
 * split is consistent when its mean agreement is at least WS_CHECK_MEAN_OK
 * and no view is below WS_CHECK_VIEW_OK. Otherwise the usual causes are
 * tried, each as a hypothesis whose mean agreement is measured the same
 * way:
 * - a frame shift: the image of frame k belongs to the camera listed for
 *   frame k + s, s = -2 .. 2, of the same transforms file (ws_scene_file;
 *   in a nerfstudio scene, whose one file holds every split, that frame
 *   may be another split's);
 * - the OpenCV convention (y down, z forward): the second and third
 *   columns of every transform_matrix negated;
 * - a wrong field of view: the focal scaled by the focal estimate below;
 * and a hypothesis is the diagnosis when it lifts the mean agreement to
 * WS_CHECK_MEAN_OK or more and above the split's own by WS_CHECK_GAIN
 * (the best such one wins). Failing that, when at most a tenth of the
 * views (at least 1) disagree and the others agree on average, those views
 * are bad frames (a wrong camera or image each); anything else is an
 * inconsistency of unknown cause. In a nerfstudio file, whose frame order,
 * convention and focal serve every split, a split that agrees under the
 * hypothesis of the split with the most views gets that cause too
 * (check.c: cause_elsewhere).
 *
 * The cross-split test: a split can agree with itself and still sit on
 * the wrong cameras. Cameras on a regular orbit or spiral, shifted by a
 * frame, turn all alike, so the split's hull is the object turned and
 * every view agrees with it; only views of another split can tell. So the
 * views of every other split are measured against the hull of the
 * reference split (the one with the most views), each split with the fix
 * found for it (its shift or flip; the focal as listed), and where one
 * disagrees (mean below WS_CHECK_MEAN_OK, a view below WS_CHECK_VIEW_OK, or
 * a mean below the reference's own by more than WS_CHECK_CROSS_GAP, which
 * lies between correct scenes and the near-symmetric solids on shifted
 * cameras: docs/RESULTS.md, "Numbers behind the code's constants") the
 * hypotheses of each file are weighed across the splits (check.c:
 * cross_check): a fault of the reference's file, under which the reference
 * still agrees with itself and the other splits agree with its hull, or of
 * a disagreeing split's own file. Its diagnosis names the file and the
 * agreement it measured; a split no hypothesis brings to agree has an
 * unknown cause.
 *
 * The focal estimate: for cameras aimed at the object a focal error looks
 * almost like a scaled object (only perspective tells them apart), so the
 * conservative hull above hides it. The focal is therefore estimated on a
 * tight hull (hull.h): the scale 2^x, x in [-1, 1], whose tight hull gives
 * the highest mean agreement (steps of 1/4 in x, then on a hull twice as
 * fine around the best down to 1/16; on at most 24 of the split's images;
 * check.c). Every hypothesis keeps each camera's principal point as
 * listed. An inconsistent split tries it as its focal hypothesis; a split
 * that passes the test above and has at least WS_CHECK_FOCAL_VIEWS views
 * (fewer make the tight mean too noisy) still has a wrong focal when the
 * estimate is off 1 by more than a factor WS_CHECK_FOCAL_OFF, lifts the
 * tight mean agreement by more than WS_CHECK_FOCAL_GAIN over the listed
 * focal, and that lift is at least WS_CHECK_FOCAL_EXPLAINS of what the
 * tight hull misses at the listed focal (1 - its mean): a thin or
 * self-similar object (a coil) loses parts of a tight hull at every focal,
 * and a focal that wins back a small share of them is noise of the
 * voxel grid, not the cause (docs/RESULTS.md "check: false alarms"). */
#ifndef WS_GEOMETRY_CHECK_H
#define WS_GEOMETRY_CHECK_H
#include "geometry/silhouette.h"
#include "io/scene.h"
#include "nn/base/status.h"

#define WS_CHECK_MEAN_OK 0.98
#define WS_CHECK_VIEW_OK 0.9
#define WS_CHECK_GAIN 0.005
#define WS_CHECK_CROSS_GAP 0.003
#define WS_CHECK_RESOLUTION 64
#define WS_CHECK_FOCAL_OFF 1.1
#define WS_CHECK_FOCAL_GAIN 0.003
#define WS_CHECK_FOCAL_EXPLAINS 0.5
#define WS_CHECK_FOCAL_VIEWS 8
#define WS_CHECK_LINE 1024 /* bytes of the report's one line */
/* A silhouette that is empty, or holds at least this share of the pixels
 * on its frame's edge, shows no object: the edge is where the background
 * colour is read (silhouette.h), and over a busy background the colour
 * threshold calls most of it object (the box room of `scene --background
 * room`, docs/RESULTS.md "Numbers behind the code's constants"), while an
 * object on one colour touches a few edge pixels at most. A split whose
 * views are more than half such has no usable silhouette, and nothing is
 * measured. */
#define WS_CHECK_SILHOUETTE_EDGE 0.5

/* Whether n views' silhouettes show an object (1; also for n = 0): no more
 * than half of them are empty (*empty) or hold WS_CHECK_SILHOUETTE_EDGE of
 * the frame's edge or more (*edge). */
int ws_check_silhouettes_usable(const ws_silhouette *sil, int n, int *empty, int *edge);

typedef enum {
    WS_CAUSE_NONE,       /* consistent */
    WS_CAUSE_SHIFT,      /* image k belongs to the camera listed for frame k + shift */
    WS_CAUSE_OPENCV,     /* cameras in the OpenCV convention */
    WS_CAUSE_FOCAL,      /* camera_angle_x (fl_x, fl_y) wrong: the focal should be scaled by focal_scale */
    WS_CAUSE_BAD_FRAMES, /* the views in `disagree` are wrong */
    WS_CAUSE_UNKNOWN
} ws_check_cause;

typedef struct {
    int n;                /* views; 0: the split is absent */
    double *agreement;    /* n */
    double mean, worst;
    int ndisagree;
    int *disagree;        /* ndisagree view indices (in the split), agreement below WS_CHECK_VIEW_OK */
    ws_check_cause cause;
    int shift;            /* WS_CAUSE_SHIFT */
    double focal_scale;   /* WS_CAUSE_FOCAL: f_true / f_listed */
    double fixed_mean;    /* mean agreement with the fix applied; NAN where the cross-split
                             test found the fix for a split that is not the reference */
    double focal_estimate; /* the best focal scale on the tight hull */
    double tight_mean, tight_fixed; /* tight mean agreement at the listed focal, at the estimate */
    int repair_shift;     /* the shift the corrected copy applies to this split: its own, the
                             cross-split test's, or in a nerfstudio file the file's (check.c) */
    double cross, cross_worst; /* mean and worst agreement of the views with the reference
                                  split's hull, each split with its fix (above); NAN for the
                                  reference and where not measured */
    int by_cross;         /* the cause was found by the cross-split test */
    double cross_before, cross_after; /* by_cross: the agreement it measured (this split's views with
                                         the reference hull, or for the reference the other splits'
                                         views pooled) before and after the fix */
} ws_check_split;

typedef struct {
    ws_check_split split[WS_NSPLITS];
    int consistent;       /* every split */
    int no_silhouette;    /* a split has no usable silhouette (WS_CHECK_SILHOUETTE_FULL): `line`
                             says so, and nothing else was measured */
    int explained;        /* the split `line` explains; -1 when consistent */
    int reference;        /* the split the cross-split test carves (the most views); -1: none */
    char line[WS_CHECK_LINE]; /* what is wrong and how to fix it; "" when consistent */
} ws_check_report;

/* scene: loaded with its images; sil[s]: the silhouettes of split s's
 * views (silhouette.h, one per view in view order). resolution: voxels
 * along the hull's longest side (WS_CHECK_RESOLUTION). */
int ws_check_scene(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], int resolution,
                   ws_check_report *r, ws_status *st);
void ws_check_report_free(ws_check_report *r);

/* 1 when the report's only fault is a focal estimate on splits that the
 * conservative hull finds consistent (mean agreement at least
 * WS_CHECK_MEAN_OK, no view below WS_CHECK_VIEW_OK): the weakest evidence
 * the check has; or that the scene has no usable silhouette, so that the
 * cameras could not be checked at all (a capture over a busy background
 * without masks, which a fit on photo edges may still fit). `fit` warns
 * with the line then instead of refusing the scene. */
int ws_check_warning_only(const ws_check_report *r);

/* Writes a corrected copy of the scene into `out` (created if missing,
 * not the scene itself): every transforms file rewritten with the fix of
 * each frame's split (frame k re-paired with the camera listed for frame
 * k + repair_shift, in file order, and dropped where there is none; second
 * and third columns negated; bad frames dropped) and the file's focal
 * (camera_angle_x, fl_x and fl_y, at the root and in frames, for the focal
 * scale of its split, or in a nerfstudio file of the split r->explained);
 * a nerfstudio file that loses frames gets explicit train / val /
 * test_filenames of their splits, so that the k % 8 rule of a file
 * without them does not move the frames after a dropped one. Every other
 * entry of the scene directory is linked (symbolic links to absolute
 * paths). */
int ws_check_write_fixed(const ws_scene *scene, const ws_check_report *r, const char *out,
                         ws_status *st);

#endif
