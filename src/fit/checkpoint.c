/* checkpoint.c: saving and restoring a fit (see checkpoint.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>
#include "nn/base/bytes.h"
#include "fit/checkpoint.h"
#include "base/outfile.h"

#define CHECKPOINT_MAGIC "WSKCKPT"
#define CHECKPOINT_VERSION 1

static void put_state(ws_bytes_writer *w, const ws_fit_state *s) {
    ws_put_u32(w, (uint32_t)s->epoch);
    ws_put_u32(w, (uint32_t)s->batch_in_epoch);
    ws_put_u32(w, (uint32_t)s->step_in_batch);
    ws_put_u64(w, (uint64_t)s->global_step);
    ws_put_u32(w, (uint32_t)s->global_batch);
    ws_put_f64(w, s->elapsed);
    ws_put_u64(w, (uint64_t)s->skipped_steps);
    for (int i = 0; i < 4; i++) ws_put_u64(w, s->rng.s[i]);
    ws_put_u32(w, (uint32_t)s->n_train);
    for (int i = 0; i < s->n_train; i++) ws_put_u32(w, (uint32_t)s->order[i]);
    size_t np = (size_t)s->curves.n * WS_CURVE_FLOATS;
    ws_put_u32(w, (uint32_t)s->curves.n);
    ws_put_f64(w, s->curves.thickness);
    ws_put_f64(w, s->curves.overlap);
    ws_put_f64s(w, s->curves.P, np);
    ws_put_u64(w, (uint64_t)s->adam.step);
    ws_put_f64(w, s->adam.lr);
    ws_put_f64s(w, s->adam.m, np);
    ws_put_f64s(w, s->adam.v, np);
    ws_put_u32(w, (uint32_t)s->nlog);
    for (int i = 0; i < s->nlog; i++) {
        const ws_log_row *row = &s->log[i];
        ws_put_u32(w, (uint32_t)row->batch);
        ws_put_u64(w, (uint64_t)row->step);
        ws_put_f64(w, row->seconds);
        ws_put_f64(w, row->train_loss);
        ws_put_f64(w, row->val_loss);
    }
    ws_put_u32(w, (uint32_t)s->nsnap);
    ws_put_f64s(w, s->snapshots, (size_t)s->nsnap * np);
    ws_put_u64(w, (uint64_t)s->respawned);
}

/* put_state's bytes, field by field */
double ws_checkpoint_state_bytes(int n_curves, int n_train, long log_rows, long snapshots) {
    double np = (double)n_curves * WS_CURVE_FLOATS;
    return 4 * 3 + 8 + 4 + 8 + 8 + 4 * 8 + 4 + 4.0 * n_train + 4 + 8 + 8 + 8 * np + 8 + 8 + 2 * 8 * np + 4 +
           (4 + 8 + 3 * 8) * (double)log_rows + 4 + 8 * np * (double)snapshots + 8;
}

int ws_checkpoint_save(const char *path, const ws_fit_state *s, int argc,
                       const char *const *argv, ws_status *st) {
    ws_bytes_writer w = {0};
    ws_put(&w, CHECKPOINT_MAGIC, 8);
    ws_put_u32(&w, CHECKPOINT_VERSION);
    ws_put_u32(&w, (uint32_t)argc);
    for (int i = 0; i < argc; i++) ws_put_str(&w, argv[i]);
    put_state(&w, s);
    uint32_t crc = w.failed ? 0 : (uint32_t)crc32(0L, w.data, (uInt)w.len);
    ws_put_u32(&w, crc);
    if (w.failed) {
        ws_bytes_writer_free(&w);
        return ws_fail(st, WS_ENOMEM, "%s: out of memory building the checkpoint", path);
    }
    if (w.len > WS_CHECKPOINT_MAX_BYTES) {
        ws_bytes_writer_free(&w);
        return ws_fail(st, WS_EUSAGE, "%s: a checkpoint of %zu bytes is over the %zu its reader accepts", path,
                       w.len, WS_CHECKPOINT_MAX_BYTES);
    }
    ws_outfile f;
    int rc = ws_outfile_open(&f, path, st);
    if (!rc) {
        if (fwrite(w.data, 1, w.len, f.fp) == w.len)
            rc = ws_outfile_commit(&f, st);
        else {
            ws_outfile_abort(&f);
            rc = ws_fail(st, WS_EIO, "%s: cannot write the checkpoint: %s", path, strerror(errno));
        }
    }
    ws_bytes_writer_free(&w);
    return rc;
}

void ws_checkpoint_free_args(int argc, char **argv) {
    if (!argv) return;
    for (int i = 0; i < argc; i++) free(argv[i]);
    free(argv);
}

static int bad(const char *path, const char *what, ws_status *st) {
    return ws_fail(st, WS_EINPUT, "%s: corrupt checkpoint (%s)", path, what);
}

/* Reads a count and checks that `count` items of `size` bytes follow. */
static int get_count(ws_bytes_reader *r, size_t size, int *count) {
    uint32_t n = ws_get_u32(r);
    if (n > 100000000u || !ws_bytes_have(r, n, size)) {
        r->failed = 1;
        return 0;
    }
    *count = (int)n;
    return 1;
}

static int all_finite(const double *v, size_t n) {
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* What a resumed fit relies on without checking it again: a file whose
 * checksum is right may still have been made by something else. */
static int check_state(const ws_fit_state *s, const char *path, ws_status *st) {
    size_t np = (size_t)s->curves.n * WS_CURVE_FLOATS;
    if (s->n_train < 1 || s->epoch < 0 || s->batch_in_epoch < 0 ||
        s->batch_in_epoch >= s->n_train || s->step_in_batch < 0 || s->global_step < 0 ||
        s->global_batch < 0 || s->skipped_steps < 0 || !(s->elapsed >= 0 && s->elapsed < INFINITY))
        return bad(path, "schedule position", st);
    for (int i = 0; i < s->n_train; i++)
        if (s->order[i] < 0 || s->order[i] >= s->n_train) return bad(path, "view order", st);
    if (!(s->curves.thickness > 0 && s->curves.thickness < INFINITY) ||
        !(s->curves.overlap >= 0 && s->curves.overlap < 1))
        return bad(path, "curve thickness or overlap", st);
    if (!all_finite(s->curves.P, np)) return bad(path, "non-finite control point", st);
    int moments = all_finite(s->adam.m, np) && all_finite(s->adam.v, np);
    for (size_t i = 0; moments && i < np; i++) moments = s->adam.v[i] >= 0;
    if (s->adam.step < 0 || !(s->adam.lr > 0 && s->adam.lr < INFINITY) || !moments)
        return bad(path, "optimiser state", st);
    if (!all_finite(s->snapshots, (size_t)s->nsnap * np)) return bad(path, "snapshots", st);
    return WS_OK;
}

static int get_state(ws_bytes_reader *r, ws_fit_state *s, const char *path, ws_status *st) {
    memset(s, 0, sizeof *s);
    s->epoch = (int)ws_get_u32(r);
    s->batch_in_epoch = (int)ws_get_u32(r);
    s->step_in_batch = (int)ws_get_u32(r);
    s->global_step = (long)ws_get_u64(r);
    s->global_batch = (int)ws_get_u32(r);
    s->elapsed = ws_get_f64(r);
    s->skipped_steps = (long)ws_get_u64(r);
    for (int i = 0; i < 4; i++) s->rng.s[i] = ws_get_u64(r);
    if (!get_count(r, 4, &s->n_train)) return bad(path, "view order", st);
    s->order = ws_malloc((size_t)s->n_train * sizeof(int), "checkpoint", st);
    if (!s->order) return st->code;
    for (int i = 0; i < s->n_train; i++) s->order[i] = (int)ws_get_u32(r);
    int n;
    if (!get_count(r, WS_CURVE_FLOATS * 8, &n) || n < 1) return bad(path, "curves", st);
    if (ws_curves_alloc(&s->curves, n, st)) return st->code;
    s->curves.thickness = ws_get_f64(r);
    s->curves.overlap = ws_get_f64(r);
    size_t np = (size_t)n * WS_CURVE_FLOATS;
    ws_get_f64s(r, s->curves.P, np);
    long adam_step = (long)ws_get_u64(r);
    double lr = ws_get_f64(r);
    if (!ws_bytes_have(r, 2 * np, 8)) return bad(path, "optimiser state", st);
    if (ws_adam_init(&s->adam, (int)np, lr, st)) return st->code;
    s->adam.step = adam_step;
    ws_get_f64s(r, s->adam.m, np);
    ws_get_f64s(r, s->adam.v, np);
    if (!get_count(r, 4 + 8 * 4, &s->nlog)) return bad(path, "log", st);
    s->caplog = s->nlog;
    s->log = ws_calloc((size_t)s->nlog, sizeof *s->log, "checkpoint log", st);
    if (!s->log) return st->code;
    for (int i = 0; i < s->nlog; i++) {
        ws_log_row *row = &s->log[i];
        row->batch = (int)ws_get_u32(r);
        row->step = (long)ws_get_u64(r);
        row->seconds = ws_get_f64(r);
        row->train_loss = ws_get_f64(r);
        row->val_loss = ws_get_f64(r);
    }
    if (!get_count(r, np * 8, &s->nsnap)) return bad(path, "snapshots", st);
    s->capsnap = s->nsnap;
    s->snapshots = ws_malloc((size_t)s->nsnap * np * sizeof(double), "checkpoint snapshots", st);
    if (!s->snapshots) return st->code;
    ws_get_f64s(r, s->snapshots, (size_t)s->nsnap * np);
    /* Checkpoints written before respawning existed end here: none moved. */
    s->respawned = r->pos < r->len ? (long)ws_get_u64(r) : 0;
    if (r->failed || s->respawned < 0) return bad(path, "truncated state", st);
    return check_state(s, path, st);
}

int ws_checkpoint_load(const char *path, ws_fit_state *s, int *argc, char ***argv,
                       ws_status *st) {
    *argc = 0;
    *argv = NULL;
    unsigned char *data;
    size_t len;
    if (ws_read_file(path, WS_CHECKPOINT_MAX_BYTES, &data, &len, st)) return st->code;
    int rc = WS_OK;
    if (len < 20 || memcmp(data, CHECKPOINT_MAGIC, 8) != 0) {
        rc = ws_fail(st, WS_EINPUT, "%s: not a wiresketch checkpoint", path);
        goto done;
    }
    ws_bytes_reader tail = {data + len - 4, 4, 0, 0};
    if ((uint32_t)crc32(0L, data, (uInt)(len - 4)) != ws_get_u32(&tail)) {
        rc = ws_fail(st, WS_EINPUT, "%s: checksum mismatch (the file is damaged)", path);
        goto done;
    }
    ws_bytes_reader r = {data, len - 4, 8, 0};
    uint32_t version = ws_get_u32(&r);
    if (version != CHECKPOINT_VERSION) {
        rc = ws_fail(st, WS_EINPUT, "%s: unknown checkpoint version %u", path, version);
        goto done;
    }
    int n;
    if (!get_count(&r, 4, &n)) {
        rc = bad(path, "arguments", st);
        goto done;
    }
    *argv = ws_calloc((size_t)n + 1, sizeof(char *), "checkpoint arguments", st);
    if (!*argv) {
        rc = st->code;
        goto done;
    }
    for (*argc = 0; *argc < n; (*argc)++) {
        (*argv)[*argc] = ws_get_str(&r);
        if (!(*argv)[*argc]) {
            rc = bad(path, "arguments", st);
            goto done;
        }
    }
    if (s && (rc = get_state(&r, s, path, st)) != WS_OK) ws_fit_state_free(s);
done:
    if (rc) {
        ws_checkpoint_free_args(*argc, *argv);
        *argc = 0;
        *argv = NULL;
    }
    free(data);
    return rc;
}
