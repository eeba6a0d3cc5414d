/* run_record.c: config.json (see run_record.h). */
#include <cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/outfile.h"
#include "base/version.h"
#include "cli/run_record.h"

int ws_run_record_invocation_option(const char *name) {
    return !strcmp(name, "--resume") || !strcmp(name, "--config") || !strcmp(name, "--overwrite");
}

/* A list's text ("0 0 1 1 0": numbers, no spaces within) as an array of its words. */
static cJSON *list_value(const char *text) {
    cJSON *array = cJSON_CreateArray();
    char word[64];
    int used;
    while (array && sscanf(text, "%63s%n", word, &used) == 1) {
        cJSON_AddItemToArray(array, cJSON_CreateString(word));
        text += used;
    }
    return array;
}

int ws_run_record_write(const char *dir, const char *scene, int ncmdline, const char *const *cmdline,
                        const ws_report_item *settings_in, const ws_arg_kind *kinds, int n, ws_status *st) {
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", dir, WS_RUN_RECORD_FILE);
    cJSON *root = cJSON_CreateObject(), *line = cJSON_CreateArray(), *settings = cJSON_CreateObject();
    int ok = root && line && settings;
    if (ok) {
        cJSON_AddStringToObject(root, "program", "wiresketch");
        cJSON_AddStringToObject(root, "version", ws_version());
        cJSON_AddStringToObject(root, "commit", ws_build_commit());
        cJSON_AddItemToObject(root, "command_line", line);
        cJSON_AddStringToObject(root, "scene", scene);
        cJSON_AddItemToObject(root, "settings", settings);
    } else {
        cJSON_Delete(line);
        cJSON_Delete(settings);
    }
    for (int i = 0; ok && i < ncmdline; i++) cJSON_AddItemToArray(line, cJSON_CreateString(cmdline[i]));
    for (int k = 0; ok && k < n; k++) {
        const char *v = settings_in[k].value;
        cJSON *value = kinds[k] == WS_ARG_FLAG      ? cJSON_CreateBool(!strcmp(v, "yes"))
                       : kinds[k] == WS_ARG_DOUBLES ? list_value(v)
                                                    : cJSON_CreateString(v);
        ok = value && cJSON_AddItemToObject(settings, settings_in[k].key, value);
    }
    char *text = ok ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text) return ws_fail(st, WS_ENOMEM, "%s: out of memory writing the run's record", path);
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) {
        free(text);
        return st->code;
    }
    fprintf(f.fp, "%s\n", text);
    free(text);
    return ws_outfile_commit(&f, st);
}

void ws_run_record_free_args(int argc, char **argv) {
    for (int i = 0; argv && i < argc; i++) free(argv[i]);
    free(argv);
}

/* Appends a copy of text to argv (room for it was counted). */
static int push(int *argc, char **argv, const char *prefix, const char *text, ws_status *st) {
    size_t n = strlen(prefix) + strlen(text) + 1;
    if (!(argv[*argc] = ws_malloc(n, "recorded arguments", st))) return st->code;
    snprintf(argv[(*argc)++], n, "%s%s", prefix, text);
    return WS_OK;
}

int ws_run_record_read(const char *path, int *argc, char ***argv, ws_status *st) {
    *argc = 0;
    *argv = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) return ws_fail(st, WS_EINPUT, "%s: cannot open the run's record", path);
    char *text = NULL;
    long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    if (size >= 0 && size < (1L << 24) && fseek(f, 0, SEEK_SET) == 0 &&
        (text = malloc((size_t)size + 1)) && fread(text, 1, (size_t)size, f) == (size_t)size)
        text[size] = '\0';
    else {
        free(text);
        text = NULL;
    }
    fclose(f);
    if (!text) return ws_fail(st, WS_EINPUT, "%s: cannot read the run's record", path);
    cJSON *root = cJSON_Parse(text);
    free(text);
    const cJSON *scene = cJSON_GetObjectItemCaseSensitive(root, "scene");
    const cJSON *settings = cJSON_GetObjectItemCaseSensitive(root, "settings");
    if (!root || !cJSON_IsString(scene) || !cJSON_IsObject(settings)) {
        cJSON_Delete(root);
        return ws_fail(st, WS_EINPUT, "%s: not a run's record (JSON with \"scene\" and \"settings\")", path);
    }
    int room = 1;
    const cJSON *s;
    cJSON_ArrayForEach(s, settings) room += 1 + (cJSON_IsArray(s) ? cJSON_GetArraySize(s) : 1);
    *argv = ws_calloc((size_t)room + 1, sizeof(char *), "recorded arguments", st);
    int rc = *argv ? push(argc, *argv, "", scene->valuestring, st) : st->code;
    cJSON_ArrayForEach(s, settings) {
        if (rc) break;
        if (cJSON_IsBool(s)) {
            if (cJSON_IsTrue(s)) rc = push(argc, *argv, "--", s->string, st);
        } else if (cJSON_IsArray(s)) {
            rc = cJSON_GetArraySize(s) ? push(argc, *argv, "--", s->string, st) : WS_OK;
            const cJSON *x;
            cJSON_ArrayForEach(x, s) {
                if (rc) break;
                rc = cJSON_IsString(x) ? push(argc, *argv, "", x->valuestring, st)
                                       : ws_fail(st, WS_EINPUT, "%s: settings.%s: a list of numbers as text",
                                                 path, s->string);
            }
        } else if (cJSON_IsString(s)) {
            if (s->valuestring[0])
                rc = push(argc, *argv, "--", s->string, st) || push(argc, *argv, "", s->valuestring, st)
                         ? st->code
                         : WS_OK;
        } else {
            rc = ws_fail(st, WS_EINPUT, "%s: settings.%s: neither text, a boolean nor a list", path, s->string);
        }
    }
    cJSON_Delete(root);
    if (rc) {
        ws_run_record_free_args(*argc, *argv);
        *argc = 0;
        *argv = NULL;
    }
    return rc;
}

int ws_run_record_check_free(const char *dir, ws_status *st) {
    static const char *const outputs[] = {"checkpoint.bin", "curves.json", "report.html"};
    for (size_t k = 0; k < sizeof outputs / sizeof outputs[0]; k++) {
        char path[WS_PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", dir, outputs[k]);
        if (access(path, F_OK) == 0)
            return ws_fail(st, WS_EUSAGE,
                           "%s: holds another run's outputs (%s); choose another --out, replace them with "
                           "--overwrite, or continue that run with `wiresketch fit --resume %s`",
                           dir, outputs[k], dir);
    }
    return WS_OK;
}
