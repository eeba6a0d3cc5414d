/* view_targets.c: each view's silhouette and line target, made once (see
 * view_targets.h). */
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include "objective/line_target.h"
#include "objective/view_cache.h"
#include "objective/view_targets.h"

struct ws_view_targets {
    const ws_scene *scene;
    ws_silhouette *sil[WS_NSPLITS]; /* per view; in == NULL until made */
    ws_view_cache line;             /* per view: H x W */
    const ws_line_evidence *evidence; /* NULL: line targets without the hull's support */
    const ws_edge_consensus *consensus; /* NULL: silhouettes and line targets from the photos alone */
};

int ws_view_targets_create(ws_view_targets **out, const ws_scene *scene, ws_status *st) {
    ws_view_targets *t = *out = ws_calloc(1, sizeof *t, "view targets", st);
    if (!t) return st->code;
    t->scene = scene;
    for (int s = 0; s < WS_NSPLITS; s++) {
        int n = scene->split[s].n;
        if (!(t->sil[s] = ws_calloc(n ? (size_t)n : 1, sizeof *t->sil[s], "silhouettes", st))) return st->code;
    }
    return ws_view_cache_init(&t->line, scene, (size_t)scene->width * scene->height, "line targets", st);
}

void ws_view_targets_free(ws_view_targets *t) {
    if (!t) return;
    for (int s = 0; s < WS_NSPLITS; s++) {
        for (int v = 0; t->sil[s] && v < t->scene->split[s].n; v++) ws_silhouette_free(&t->sil[s][v]);
        free(t->sil[s]);
    }
    ws_view_cache_free(&t->line);
    free(t);
}

void ws_view_targets_release_setup(ws_view_targets *t) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        ws_view_cache_drop(&t->line, s);
        for (int v = 0; s != WS_TRAIN && v < t->scene->split[s].n; v++) ws_silhouette_free(&t->sil[s][v]);
    }
#ifdef __GLIBC__
    /* The freed buffers lie in the heap under later ones, where glibc keeps
     * their pages: handed back, they stay out of the fit's peak (the rose
     * with f16 weights, bench memory: 713 MB kept, 678 MB handed back). */
    malloc_trim(0);
#endif
}

/* Makes view `view`'s silhouette unless it is made already. */
static int make_silhouette(ws_view_targets *t, int split, int view, ws_status *st) {
    ws_silhouette *s = &t->sil[split][view];
    const ws_view *v = &t->scene->split[split].views[view];
    if (s->in) return WS_OK;
    return t->consensus ? ws_edge_consensus_silhouette(t->consensus, v, s, st) : ws_view_silhouette(v, s, st);
}

int ws_view_targets_silhouettes(ws_view_targets *t, int split, const ws_silhouette **out, ws_status *st) {
    for (int v = 0; v < t->scene->split[split].n; v++)
        if (make_silhouette(t, split, v, st)) return st->code;
    *out = t->sil[split];
    return WS_OK;
}

/* Fills a slot of the line cache: the view's line target. */
static int fill_line(void *ctx, int split, int view, float *slot, ws_status *st) {
    ws_view_targets *t = ctx;
    const ws_view *v = &t->scene->split[split].views[view];
    if (v->edges.data) {
        memcpy(slot, v->edges.data, t->line.floats_per_view * sizeof *slot);
        return WS_OK;
    }
    if (make_silhouette(t, split, view, st)) return st->code;
    if (t->consensus) return ws_edge_consensus_line_target(t->consensus, v, &t->sil[split][view], slot, st);
    uint8_t *support = NULL;
    if (t->evidence && (!(support = ws_malloc(t->line.floats_per_view, "line support", st)) ||
                        ws_line_evidence_view(t->evidence, &v->cam, support, st))) {
        free(support);
        return st->code;
    }
    int rc = ws_line_target(&v->photo, v->mask.data ? &v->mask : NULL, &t->sil[split][view], support, slot, st);
    free(support);
    return rc;
}

void ws_view_targets_set_evidence(ws_view_targets *t, const ws_line_evidence *e) { t->evidence = e; }

void ws_view_targets_set_consensus(ws_view_targets *t, const ws_edge_consensus *c) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        ws_view_cache_drop(&t->line, s);
        for (int v = 0; v < t->scene->split[s].n; v++) ws_silhouette_free(&t->sil[s][v]);
    }
    t->consensus = c;
}

int ws_view_targets_line(ws_view_targets *t, int split, int view, const float **out, ws_status *st) {
    return ws_view_cache_get(&t->line, split, view, fill_line, t, out, st);
}
