/* Scenario documents: parse with error position, load, override. */
#include "sim/scenario_document.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILE_BYTES (16L * 1024L * 1024L)
#define SNIPPET_CHARS  24

/* Line/column (1-based) of pos in text, and the text found there. */
static void syntax_error(const char *text, const char *pos, scn_error_t *err)
{
    int line = 1;
    int column = 1;
    for (const char *c = text; c < pos; c++) {
        if (*c == '\n') {
            line++;
            column = 1;
        } else {
            column++;
        }
    }
    char found[SNIPPET_CHARS + 8];
    size_t n = 0;
    while (pos[n] != '\0' && pos[n] != '\n' && n < SNIPPET_CHARS) {
        n++;
    }
    if (pos[0] == '\0') {
        snprintf(found, sizeof(found), "end of input");
    } else if (n == 0) {
        snprintf(found, sizeof(found), "end of line");
    } else {
        snprintf(found, sizeof(found), "'%.*s'", (int)n, pos);
    }
    scenario_error_set(err, SCN_ERR_SYNTAX, NULL, "JSON value", found);
    err->line = line;
    err->column = column;
}

cJSON *scenario_document_parse(const char *text, const char *file, scn_error_t *err)
{
    scenario_error_set_file(err, file);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, true);
    if (root == NULL) {
        syntax_error(text, end != NULL ? end : text, err);
    }
    return root;
}

cJSON *scenario_document_load(const char *file, scn_error_t *err)
{
    scenario_error_set_file(err, file);
    FILE *f = fopen(file, "rb");
    if (f == NULL) {
        scenario_error_set(err, SCN_ERR_IO, NULL, "a readable JSON file", strerror(errno));
        return NULL;
    }
    char *text = NULL;
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0) {
        size = ftell(f);
    }
    if (size >= 0 && size <= MAX_FILE_BYTES && fseek(f, 0, SEEK_SET) == 0) {
        text = malloc((size_t)size + 1);
    }
    if (text == NULL || fread(text, 1, (size_t)size, f) != (size_t)size) {
        scenario_error_set(err, SCN_ERR_IO, NULL, "a readable JSON file of at most 16 MiB",
                           size > MAX_FILE_BYTES ? "a larger file" : "a read error");
        free(text);
        fclose(f);
        return NULL;
    }
    fclose(f);
    text[size] = '\0';
    cJSON *root = scenario_document_parse(text, file, err);
    free(text);
    return root;
}

/* One step of a key path: an object key or an array index. */
typedef struct {
    bool is_index;
    char name[SCN_PATH_MAX];
    int index;
} path_step_t;

/* Reads the step at *p and advances *p past it (and past a following '.').
 * Returns false on a malformed path. *more is true when another step follows. */
static bool next_step(const char **p, path_step_t *step, bool *more)
{
    const char *c = *p;
    if (*c == '[') {
        c++;
        if (!isdigit((unsigned char)*c)) {
            return false;
        }
        long index = 0;
        while (isdigit((unsigned char)*c) && index < 1000000) {
            index = index * 10 + (*c - '0');
            c++;
        }
        if (*c != ']') {
            return false;
        }
        c++;
        step->is_index = true;
        step->index = (int)index;
    } else {
        size_t n = strcspn(c, ".[");
        if (n == 0 || n >= sizeof(step->name)) {
            return false;
        }
        memcpy(step->name, c, n);
        step->name[n] = '\0';
        step->is_index = false;
        c += n;
    }
    if (*c == '.') {
        c++;
        if (*c == '\0' || *c == '[') {
            return false;
        }
    } else if (*c != '\0' && *c != '[') {
        return false;
    }
    *more = *c != '\0';
    *p = c;
    return true;
}

static bool override_error(scn_error_t *err, const char *path, const char *expected,
                           const char *found)
{
    scenario_error_set(err, SCN_ERR_OVERRIDE, path, expected, found);
    return false;
}

/* Put value at step inside container; takes ownership of value on success. */
static bool assign(cJSON *container, const path_step_t *step, cJSON *value)
{
    if (step->is_index) {
        if (!cJSON_IsArray(container)) {
            return false;
        }
        int size = cJSON_GetArraySize(container);
        if (step->index == size) {
            return cJSON_AddItemToArray(container, value);
        }
        return step->index < size && cJSON_ReplaceItemInArray(container, step->index, value);
    }
    if (!cJSON_IsObject(container)) {
        return false;
    }
    if (cJSON_GetObjectItemCaseSensitive(container, step->name) != NULL) {
        return cJSON_ReplaceItemInObjectCaseSensitive(container, step->name, value);
    }
    return cJSON_AddItemToObject(container, step->name, value);
}

/* Child of container at step; creates a missing object member when create. */
static cJSON *descend(cJSON *container, const path_step_t *step, bool create)
{
    if (step->is_index) {
        return cJSON_IsArray(container) ? cJSON_GetArrayItem(container, step->index) : NULL;
    }
    if (!cJSON_IsObject(container)) {
        return NULL;
    }
    cJSON *child = cJSON_GetObjectItemCaseSensitive(container, step->name);
    if (child == NULL && create) {
        child = cJSON_AddObjectToObject(container, step->name);
    }
    return child;
}

bool scenario_document_set(cJSON *root, const char *assignment, scn_error_t *err)
{
    const char *eq = strchr(assignment, '=');
    char path[SCN_PATH_MAX];
    size_t path_len = eq != NULL ? (size_t)(eq - assignment) : 0;
    if (eq == NULL) {
        return override_error(err, assignment, "KEY.PATH=VALUE", "no '='");
    }
    if (path_len == 0 || path_len >= sizeof(path)) {
        char expected[80];
        snprintf(expected, sizeof(expected), "KEY.PATH=VALUE, KEY.PATH of 1 to %d characters",
                 SCN_PATH_MAX - 1);
        return override_error(err, assignment, expected,
                              path_len == 0 ? "no key path before '='" : "a longer key path");
    }
    memcpy(path, assignment, path_len);
    path[path_len] = '\0';

    const char *p = path;
    path_step_t step;
    bool more = false;
    if (!next_step(&p, &step, &more)) {
        return override_error(err, path, "keys separated by '.', indexes as [i]", path);
    }
    cJSON *container = root;
    while (more) {
        path_step_t next;
        const char *after = p;
        if (!next_step(&after, &next, &more)) {
            return override_error(err, path, "keys separated by '.', indexes as [i]", path);
        }
        cJSON *child = descend(container, &step, !next.is_index);
        if (!cJSON_IsObject(child) && !cJSON_IsArray(child)) {
            return override_error(err, path, "a path through existing arrays or objects",
                                  child == NULL ? "no such element" : "a non-container value");
        }
        container = child;
        step = next;
        p = after;
    }

    const char *text = eq + 1;
    cJSON *value = cJSON_ParseWithOpts(text, NULL, true);
    if (value == NULL) {
        value = cJSON_CreateString(text);
    }
    if (value == NULL || !assign(container, &step, value)) {
        cJSON_Delete(value);
        return override_error(err, path, "an object key or an array index up to the array size",
                              "no place to put the value");
    }
    return true;
}
