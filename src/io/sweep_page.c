/* sweep_page.c: a sweep's contact sheet and page (see sweep_page.h). */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/limits.h"
#include "base/outfile.h"
#include "base/paths.h"
#include "io/html.h"
#include "io/image.h"
#include "io/label.h"
#include "io/sweep_page.h"
#include "nn/base/bytes.h"

#define GAP 4 /* pixels of white between the contact sheet's cells */
/* A contact sheet's float pixels at the most: 1024 runs of 6 cells of 128
 * pixels take 1.3 GB */
#define MAX_SHEET_BYTES ((size_t)2 << 30)

/* The contact sheet's rows are named (the photos, then each run) in a
 * strip above their cells: the font at twice its size from 96 px cells. */
static int label_scale(int cell) { return cell >= 96 ? 2 : 1; }
static int label_height(int cell) { return WS_LABEL_HEIGHT * label_scale(cell) + 4; }

/* The test views' names of a finished run (from its metrics-free test/
 * folder: r_K.png beside r_K_photo.png), in order K = 0, 1, ... */
static int test_view_name(const char *dir, int k, char *name, size_t size) {
    snprintf(name, size, "r_%d", k);
    char path[WS_PATH_MAX + 128];
    snprintf(path, sizeof path, "%s/test/%s.png", dir, name);
    return access(path, F_OK) == 0;
}

static double metric(const cJSON *m, const char *key) {
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(m, key);
    return cJSON_IsNumber(x) ? x->valuedouble : NAN;
}

static void put_number(FILE *f, double v, const char *fmt) {
    if (isfinite(v))
        fprintf(f, fmt, v);
    else
        fputs("&ndash;", f);
}

/* Pastes the PNG at path (resampled to cell x cell) into the sheet at cell
 * (row, col), below the row's label; a missing image leaves the cell grey. */
static void paste(ws_image *sheet, const char *path, int row, int col, int cell) {
    static const float white[3] = {1, 1, 1};
    ws_image img;
    ws_status st;
    int ok = access(path, F_OK) == 0 && ws_image_read(path, cell, cell, white, &img, &st) == WS_OK;
    const size_t plane = (size_t)sheet->width * sheet->height;
    for (int i = 0; i < cell; i++)
        for (int j = 0; j < cell; j++)
            for (int c = 0; c < 3; c++) {
                size_t at = (size_t)(GAP + row * (label_height(cell) + cell + GAP) + label_height(cell) + i) *
                                sheet->width +
                            GAP + col * (cell + GAP) + j;
                sheet->data[c * plane + at] = ok ? img.data[((size_t)c * cell + i) * cell + j] : 0.5f;
            }
    if (ok) ws_image_free(&img);
}

/* The contact sheet's width and height for nviews test views per row:
 * the cells (the photos' row and one per run) and wide enough for every
 * row's name. */
static void sheet_size(const ws_sweep_page *p, int nviews, size_t *width, size_t *height) {
    *width = GAP + (size_t)nviews * (p->cell + GAP);
    for (int k = 0; k < p->nruns; k++) {
        size_t w = 2 * GAP + strlen(p->runs[k]) * WS_LABEL_ADVANCE * label_scale(p->cell);
        if (w > *width) *width = w;
    }
    *height = GAP + (size_t)(p->nruns + 1) * (label_height(p->cell) + p->cell + GAP);
}

int ws_sweep_page_check(const ws_sweep_page *p, ws_status *st) {
    char what[200];
    snprintf(what, sizeof what, "sweep: the contact sheet of %d runs with --sheet-views %d --sheet-cell %d", p->nruns,
             p->views, p->cell);
    size_t bytes, f[4] = {0, 0, 3, sizeof(float)};
    sheet_size(p, p->views, &f[0], &f[1]);
    if (ws_size_product(what, f, 4, MAX_SHEET_BYTES, "a contact sheet", &bytes, st)) st->code = WS_EUSAGE;
    return st->code;
}

int ws_sweep_page_write(const ws_sweep_page *p, ws_status *st) {
    char first[WS_PATH_MAX], view[64], path[WS_PATH_MAX + 128]; /* a file of a run's folder */
    int nviews = 0;
    snprintf(first, sizeof first, "%s/%s", p->out, p->runs[0]);
    while (nviews < p->views && test_view_name(first, nviews, view, sizeof view)) nviews++;
    if (nviews == 0) return ws_fail(st, WS_EINPUT, "%s/test: no test renders to show (a scene without a test split?)", first);
    ws_image sheet;
    const int cell = p->cell;
    const int pitch = label_height(cell) + cell + GAP;
    size_t width, height;
    sheet_size(p, nviews, &width, &height);
    if (ws_image_alloc(&sheet, (int)width, (int)height, 3, st)) return st->code;
    for (size_t k = 0; k < (size_t)sheet.width * sheet.height * 3; k++) sheet.data[k] = 1;
    ws_label_draw(&sheet, GAP, GAP + 2, "photos", label_scale(cell), 0);
    snprintf(path, sizeof path, "%s/index.html", p->out);
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) {
        ws_image_free(&sheet);
        return st->code;
    }
    FILE *h = f.fp;
    fputs("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>wiresketch sweep</title>\n"
          "<style>body{font-family:sans-serif;margin:1em}table{border-collapse:collapse}"
          "td,th{border:1px solid #ccc;padding:4px;vertical-align:top;font-size:13px}"
          "img{display:block}</style></head><body>\n<h1>wiresketch sweep</h1>\n<p>scene ", h);
    ws_html_text(h, p->scene);
    fprintf(h, "; contact sheet: <a href=\"contact_sheet.png\">contact_sheet.png</a> (row 1: the photos, "
               "then one row per run in this order, each named above its images)</p>\n<table>\n<tr><th>run</th><th>test loss</th>"
               "<th>Chamfer / diag.</th><th>F-score</th><th>surface mean / diag.</th><th>steps</th>"
               "<th>time (s)</th>");
    for (int v = 0; v < nviews; v++) {
        test_view_name(first, v, view, sizeof view);
        snprintf(path, sizeof path, "%s/test/%s_photo.png", first, view);
        paste(&sheet, path, 0, v, cell);
        fprintf(h, "<th>%s<br><img src=\"", view);
        ws_html_url(h, p->runs[0]);
        fprintf(h, "/test/%s_photo.png\" width=\"%d\"></th>", view, cell);
    }
    fputs("</tr>\n", h);
    for (int k = 0; k < p->nruns; k++) {
        char dir[WS_PATH_MAX];
        const char *name = p->runs[k];
        ws_label_draw(&sheet, GAP, GAP + (k + 1) * pitch + 2, name, label_scale(cell), 0);
        snprintf(dir, sizeof dir, "%s/%s", p->out, name);
        snprintf(path, sizeof path, "%s/metrics.json", dir);
        unsigned char *bytes = NULL;
        size_t len = 0;
        ws_status ignored;
        cJSON *m = ws_read_file(path, (size_t)1 << 20, &bytes, &len, &ignored) == WS_OK
                       ? cJSON_ParseWithLength((const char *)bytes, len)
                       : NULL;
        free(bytes);
        fputs("<tr><td><a href=\"", h);
        ws_html_url(h, name);
        fputs("/report.html\">", h);
        ws_html_text(h, name);
        fputs("</a></td>", h);
        /* the columns of the header, from the run's metrics.json */
        static const char *const columns[][2] = {{"test_loss", "%.5g"}, {"chamfer", "%.4f"},
                                                 {"fscore", "%.3f"},    {"surface_mean", "%.4f"},
                                                 {"steps", "%.0f"},     {"seconds", "%.1f"}};
        for (size_t c = 0; c < sizeof columns / sizeof columns[0]; c++) {
            fputs("<td>", h);
            put_number(h, metric(m, columns[c][0]), columns[c][1]);
            fputs("</td>", h);
        }
        cJSON_Delete(m);
        for (int v = 0; v < nviews; v++) {
            test_view_name(first, v, view, sizeof view);
            snprintf(path, sizeof path, "%s/test/%s.png", dir, view);
            paste(&sheet, path, k + 1, v, cell);
            fputs("<td><img src=\"", h);
            ws_html_url(h, name);
            fprintf(h, "/test/%s.png\" width=\"%d\"></td>", view, cell);
        }
        fputs("</tr>\n", h);
    }
    fputs("</table>\n</body></html>\n", h);
    int rc = ws_outfile_commit(&f, st);
    snprintf(path, sizeof path, "%s/contact_sheet.png", p->out);
    if (!rc) rc = ws_png_write(path, &sheet, st);
    ws_image_free(&sheet);
    return rc;
}

