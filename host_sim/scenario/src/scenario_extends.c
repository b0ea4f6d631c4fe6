/* Scenario files that extend another one; see sim/scenario_extends.h. */
#define _POSIX_C_SOURCE 200809L
#include "sim/scenario_extends.h"

#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "sim/json_reader.h"
#include "sim/scenario.h"
#include "sim/scenario_document.h"

#define FILE_PATH_MAX   512
#define MAX_SET_ENTRIES 1000

/* One file of the chain being resolved: its path and, when it could be
 * stat'ed, its identity (so "a.json" and "dir/../a.json" are one file). */
typedef struct {
    char file[FILE_PATH_MAX];
    bool has_id;
    dev_t dev;
    ino_t ino;
} chain_link_t;

typedef struct {
    chain_link_t links[SCENARIO_EXTENDS_MAX_DEPTH + 1];
    size_t n;
} chain_t;

/* What an extending file says besides "set" (read in place, not copied). */
typedef struct {
    char extends[FILE_PATH_MAX];
    char name[SCENARIO_NAME_MAX];
    char description[SCENARIO_DESCRIPTION_MAX];
    bool has_name, has_description;
    jr_array_t set;
} extending_t;

static bool fail(scn_error_t *err, const char *file, scn_status_t code, const char *path,
                 const char *expected, const char *found)
{
    if (err->code == SCN_OK) {
        scenario_error_set_file(err, file);
        scenario_error_set(err, code, path, expected, found);
    }
    return false;
}

static void push_link(chain_t *chain, const char *file)
{
    chain_link_t *link = &chain->links[chain->n++];
    struct stat st;
    snprintf(link->file, sizeof(link->file), "%s", file != NULL ? file : "");
    link->has_id = file != NULL && stat(file, &st) == 0;
    if (link->has_id) {
        link->dev = st.st_dev;
        link->ino = st.st_ino;
    }
}

static bool in_chain(const chain_t *chain, const chain_link_t *link)
{
    for (size_t i = 0; link->has_id && i + 1 < chain->n; i++) {
        const chain_link_t *other = &chain->links[i];
        if (other->has_id && other->dev == link->dev && other->ino == link->ino) {
            return true;
        }
    }
    return false;
}

/* "a.json -> b.json -> a.json" into buf. */
static void chain_text(const chain_t *chain, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < chain->n && used < size; i++) {
        int n =
            snprintf(buf + used, size - used, "%s%s", i > 0 ? " -> " : "", chain->links[i].file);
        used += n > 0 ? (size_t)n : 0;
    }
}

/* The extending file's own keys; only extends, set, name and description. */
static bool read_extending(const cJSON *doc, extending_t *x, scn_error_t *err)
{
    jr_object_t root;
    bool ok = jr_root(&root, doc, err) &&
              jr_string_opt(&root, "extends", "", x->extends, sizeof(x->extends)) &&
              jr_array_opt(&root, "set", 0, MAX_SET_ENTRIES, &x->set) &&
              jr_string_opt(&root, "name", "", x->name, sizeof(x->name)) &&
              jr_string_opt(&root, "description", "", x->description, sizeof(x->description)) &&
              jr_finish(&root);
    if (ok && x->extends[0] == '\0') {
        jr_fail(&root, "extends", SCN_ERR_INVALID, "the path of the base scenario file",
                "an empty string");
        ok = false;
    }
    for (size_t i = 0; ok && i < x->set.size; i++) {
        const cJSON *entry = cJSON_GetArrayItem(x->set.json, (int)i);
        if (!cJSON_IsString(entry)) {
            char key[32];
            char found[SCN_TEXT_MAX];
            snprintf(key, sizeof(key), "set[%zu]", i);
            jr_describe(entry, found, sizeof(found));
            jr_fail(&root, key, SCN_ERR_TYPE, "string \"KEY.PATH=VALUE\"", found);
            ok = false;
        }
    }
    x->has_name = cJSON_GetObjectItemCaseSensitive(doc, "name") != NULL;
    x->has_description = cJSON_GetObjectItemCaseSensitive(doc, "description") != NULL;
    return ok;
}

/* The base's path: relative to the extending file's directory. */
static bool base_path(const char *file, const char *extends, char *out, size_t size,
                      scn_error_t *err)
{
    const char *slash = file != NULL ? strrchr(file, '/') : NULL;
    int dir_len = slash != NULL && extends[0] != '/' ? (int)(slash - file + 1) : 0;
    int n = snprintf(out, size, "%.*s%s", dir_len, dir_len > 0 ? file : "", extends);
    if (n < 0 || (size_t)n >= size) {
        char expected[64];
        snprintf(expected, sizeof(expected), "a base path of at most %zu characters", size - 1);
        return fail(err, file, SCN_ERR_RANGE, "extends", expected, "a longer path");
    }
    return true;
}

static cJSON *resolve(cJSON *doc, chain_t *chain, scn_error_t *err);

/* Load, check and resolve the base of the file at the chain's end. */
static cJSON *load_base(const char *extends, chain_t *chain, scn_error_t *err)
{
    const char *file = chain->links[chain->n - 1].file;
    char path[FILE_PATH_MAX];
    char found[SCN_TEXT_MAX];
    if (!base_path(file, extends, path, sizeof(path), err)) {
        return NULL;
    }
    if (chain->n > SCENARIO_EXTENDS_MAX_DEPTH) {
        char expected[64];
        chain_text(chain, found, sizeof(found));
        snprintf(expected, sizeof(expected), "at most %d levels of \"extends\"",
                 SCENARIO_EXTENDS_MAX_DEPTH);
        size_t used = strlen(found);
        if (snprintf(found + used, sizeof(found) - used, " -> %s", path) < 0) {
            found[used] = '\0';
        }
        fail(err, file, SCN_ERR_INVALID, "extends", expected, found);
        return NULL;
    }
    scn_error_t load_err;
    scenario_error_clear(&load_err);
    cJSON *base = scenario_document_load(path, &load_err);
    if (base == NULL && load_err.code == SCN_ERR_IO) {
        snprintf(found, sizeof(found), "%.300s: %.200s", path, load_err.found);
        fail(err, file, SCN_ERR_IO, "extends", "a readable base scenario file", found);
        return NULL;
    }
    if (base == NULL) {
        *err = load_err; /* malformed base: its own file, line and column */
        return NULL;
    }
    push_link(chain, path);
    if (in_chain(chain, &chain->links[chain->n - 1])) {
        chain_text(chain, found, sizeof(found));
        fail(err, file, SCN_ERR_INVALID, "extends", "no file twice in a chain of \"extends\"",
             found);
        cJSON_Delete(base);
        return NULL;
    }
    base = resolve(base, chain, err);
    chain->n--;
    return base;
}

/* name/description of the extending file replace the base's. */
static void replace_string(cJSON *doc, const char *key, bool present, const char *value)
{
    cJSON_DeleteItemFromObjectCaseSensitive(doc, key);
    if (present) {
        cJSON_AddStringToObject(doc, key, value);
    }
}

/* Apply set[i]; a failure is reported at "set[i]" of the extending file. */
static bool apply_set(cJSON *doc, const char *file, const jr_array_t *set, scn_error_t *err)
{
    for (size_t i = 0; i < set->size; i++) {
        const char *entry = cJSON_GetArrayItem(set->json, (int)i)->valuestring;
        scn_error_t set_err;
        scenario_error_clear(&set_err);
        if (!scenario_document_set(doc, entry, &set_err)) {
            char key[32];
            char found[SCN_TEXT_MAX];
            snprintf(key, sizeof(key), "set[%zu]", i);
            snprintf(found, sizeof(found), "%.200s (key path \"%.200s\")", set_err.found,
                     set_err.path);
            return fail(err, file, SCN_ERR_OVERRIDE, key, set_err.expected, found);
        }
    }
    return true;
}

/* doc is the file at the chain's end; takes ownership. */
static cJSON *resolve(cJSON *doc, chain_t *chain, scn_error_t *err)
{
    if (!cJSON_IsObject(doc) || cJSON_GetObjectItemCaseSensitive(doc, "extends") == NULL) {
        return doc;
    }
    const char *file = chain->links[chain->n - 1].file;
    extending_t x_storage; /* about 1.6 kB a level, SCENARIO_EXTENDS_MAX_DEPTH + 1 levels */
    extending_t *x = &x_storage;
    memset(x, 0, sizeof(*x));
    scenario_error_set_file(err, file);
    cJSON *base = read_extending(doc, x, err) ? load_base(x->extends, chain, err) : NULL;
    bool ok = base != NULL;
    if (ok) {
        replace_string(base, "name", x->has_name, x->name);
        replace_string(base, "description", x->has_description, x->description);
        ok = apply_set(base, file, &x->set, err);
    }
    cJSON_Delete(doc);
    if (!ok) {
        cJSON_Delete(base);
        return NULL;
    }
    return base;
}

cJSON *scenario_extends_resolve(cJSON *doc, const char *file, scn_error_t *err)
{
    chain_t chain = { .n = 0 };
    push_link(&chain, file);
    cJSON *merged = resolve(doc, &chain, err);
    if (merged != NULL) {
        scenario_error_set_file(err, file);
    }
    return merged;
}
