/* Validating reader over a cJSON tree; see sim/json_reader.h. */
#include "sim/json_reader.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define MAX_EXACT_INTEGER 9007199254740992.0 /* 2^53 */

static bool failed(const scn_error_t *err)
{
    return err->code != SCN_OK;
}

/* A path longer than SCN_PATH_MAX - 1 keeps its start and ends in "...". */
static void mark_if_truncated(char *dst, int written)
{
    if (written >= SCN_PATH_MAX) {
        memcpy(dst + SCN_PATH_MAX - 4, "...", 4);
    }
}

static void join_key(char *dst, const char *parent, const char *key)
{
    int written = parent[0] == '\0' ? snprintf(dst, SCN_PATH_MAX, "%s", key)
                                    : snprintf(dst, SCN_PATH_MAX, "%s.%s", parent, key);
    mark_if_truncated(dst, written);
}

static void join_index(char *dst, const char *parent, size_t i)
{
    mark_if_truncated(dst, snprintf(dst, SCN_PATH_MAX, "%s[%zu]", parent, i));
}

void jr_describe(const cJSON *item, char *buf, size_t size)
{
    if (cJSON_IsNumber(item)) {
        if (isinf(item->valuedouble)) {
            snprintf(buf, size, "%sinf", item->valuedouble < 0 ? "-" : "");
        } else {
            snprintf(buf, size, "%.10g", item->valuedouble);
        }
    } else if (cJSON_IsString(item)) {
        snprintf(buf, size, "string \"%.60s\"", item->valuestring);
    } else if (cJSON_IsBool(item)) {
        snprintf(buf, size, "%s", cJSON_IsTrue(item) ? "true" : "false");
    } else if (cJSON_IsNull(item)) {
        snprintf(buf, size, "null");
    } else if (cJSON_IsArray(item)) {
        snprintf(buf, size, "array of %d elements", cJSON_GetArraySize(item));
    } else if (cJSON_IsObject(item)) {
        snprintf(buf, size, "object");
    } else {
        snprintf(buf, size, "invalid value");
    }
}

static void fail_at(scn_error_t *err, scn_status_t code, const char *path, const char *expected,
                    const cJSON *found)
{
    char text[SCN_TEXT_MAX] = "";
    if (found != NULL) {
        jr_describe(found, text, sizeof(text));
    }
    scenario_error_set(err, code, path, expected, text);
}

static void range_text(jr_range_t r, char *buf, size_t size)
{
    if (r.lo <= JR_ANY_FINITE.lo && r.hi >= JR_ANY_FINITE.hi) {
        snprintf(buf, size, "finite number");
        return;
    }
    snprintf(buf, size, "number in %c%.6g, %.6g%c", r.lo_open ? '(' : '[', r.lo, r.hi,
             r.hi_open ? ')' : ']');
}

static bool in_range(double v, jr_range_t r)
{
    bool above_lo = r.lo_open ? v > r.lo : v >= r.lo;
    bool below_hi = r.hi_open ? v < r.hi : v <= r.hi;
    return above_lo && below_hi;
}

/* Check that item is a finite number; a wrong type names expected. */
static bool check_finite(const cJSON *item, const char *path, const char *expected,
                         scn_error_t *err)
{
    if (!cJSON_IsNumber(item)) {
        fail_at(err, SCN_ERR_TYPE, path, expected, item);
        return false;
    }
    if (!isfinite(item->valuedouble)) {
        fail_at(err, SCN_ERR_NONFINITE, path, "finite number", item);
        return false;
    }
    return true;
}

/* Check that item is a finite number in range; path names it in errors. */
static bool check_number(const cJSON *item, const char *path, jr_range_t range, scn_error_t *err,
                         double *out)
{
    char expected[96];
    range_text(range, expected, sizeof(expected));
    if (!check_finite(item, path, expected, err)) {
        return false;
    }
    if (!in_range(item->valuedouble, range)) {
        fail_at(err, SCN_ERR_RANGE, path, expected, item);
        return false;
    }
    *out = item->valuedouble;
    return true;
}

/* Register key as known and look it up. Returns false after an earlier error. */
static bool lookup(jr_object_t *obj, const char *key, const cJSON **item, char *path)
{
    if (failed(obj->err)) {
        return false;
    }
    join_key(path, obj->path, key);
    if (obj->n_known == JR_MAX_KEYS) {
        /* A reader declaring more keys than it can track is a bug of the
         * reader, reported as such rather than as the user's unknown key. */
        scenario_error_set(obj->err, SCN_ERR_INVALID, path,
                           "at most JR_MAX_KEYS keys read from one object (reader limit)", "");
        return false;
    }
    obj->known[obj->n_known++] = key;
    *item = obj->json != NULL ? cJSON_GetObjectItemCaseSensitive(obj->json, key) : NULL;
    return true;
}

static bool missing(jr_object_t *obj, const char *path, const char *expected)
{
    scenario_error_set(obj->err, SCN_ERR_MISSING, path, expected, NULL);
    return false;
}

/* lookup, then report a required key that is absent (expected says what it
 * should have been). Returns false after an error; otherwise *item is NULL
 * for an absent optional key. */
static bool lookup_value(jr_object_t *obj, const char *key, bool required, const char *expected,
                         const cJSON **item, char *path)
{
    if (!lookup(obj, key, item, path)) {
        return false;
    }
    if (*item == NULL && required) {
        return missing(obj, path, expected);
    }
    return true;
}

static void init_object(jr_object_t *obj, const cJSON *json, const char *path, scn_error_t *err)
{
    obj->json = json;
    snprintf(obj->path, sizeof(obj->path), "%s", path);
    obj->err = err;
    obj->n_known = 0;
}

bool jr_root(jr_object_t *root, const cJSON *json, scn_error_t *err)
{
    init_object(root, NULL, "", err);
    if (failed(err)) {
        return false;
    }
    if (!cJSON_IsObject(json)) {
        fail_at(err, SCN_ERR_TYPE, "(root)", "object", json);
        return false;
    }
    root->json = json;
    return true;
}

bool jr_ok(const jr_object_t *obj)
{
    return !failed(obj->err);
}

const cJSON *jr_peek(const jr_object_t *obj, const char *key)
{
    if (failed(obj->err) || obj->json == NULL) {
        return NULL;
    }
    return cJSON_GetObjectItemCaseSensitive(obj->json, key);
}

static bool object_impl(jr_object_t *obj, const char *key, bool required, jr_object_t *child)
{
    const cJSON *item;
    char path[SCN_PATH_MAX];
    if (!lookup(obj, key, &item, path)) {
        init_object(child, NULL, "", obj->err);
        return false;
    }
    init_object(child, NULL, path, obj->err);
    if (item == NULL) {
        return required ? missing(obj, path, "object") : true;
    }
    if (!cJSON_IsObject(item)) {
        fail_at(obj->err, SCN_ERR_TYPE, path, "object", item);
        return false;
    }
    child->json = item;
    return true;
}

bool jr_object(jr_object_t *obj, const char *key, jr_object_t *child)
{
    return object_impl(obj, key, true, child);
}

bool jr_object_opt(jr_object_t *obj, const char *key, jr_object_t *child)
{
    return object_impl(obj, key, false, child);
}

static bool number_impl(jr_object_t *obj, const char *key, jr_range_t range, bool required,
                        double def, double *out)
{
    char expected[96];
    range_text(range, expected, sizeof(expected));
    const cJSON *item;
    char path[SCN_PATH_MAX];
    if (!lookup_value(obj, key, required, expected, &item, path)) {
        return false;
    }
    if (item == NULL) {
        *out = def;
        return true;
    }
    return check_number(item, path, range, obj->err, out);
}

bool jr_number(jr_object_t *obj, const char *key, jr_range_t range, double *out)
{
    return number_impl(obj, key, range, true, 0.0, out);
}

bool jr_number_opt(jr_object_t *obj, const char *key, jr_range_t range, double def, double *out)
{
    return number_impl(obj, key, range, false, def, out);
}

static bool uint_impl(jr_object_t *obj, const char *key, uint64_t lo, uint64_t hi, bool required,
                      uint64_t def, uint64_t *out)
{
    char expected[96];
    snprintf(expected, sizeof(expected), "whole number in [%llu, %llu]", (unsigned long long)lo,
             (unsigned long long)hi);
    const cJSON *item;
    char path[SCN_PATH_MAX];
    if (!lookup_value(obj, key, required, expected, &item, path)) {
        return false;
    }
    if (item == NULL) {
        *out = def;
        return true;
    }
    if (!check_finite(item, path, expected, obj->err)) {
        return false;
    }
    double v = item->valuedouble;
    if (v != floor(v)) {
        fail_at(obj->err, SCN_ERR_TYPE, path, expected, item);
        return false;
    }
    if (v < (double)lo || v > (double)hi || v > MAX_EXACT_INTEGER) {
        fail_at(obj->err, SCN_ERR_RANGE, path, expected, item);
        return false;
    }
    *out = (uint64_t)v;
    return true;
}

bool jr_uint(jr_object_t *obj, const char *key, uint64_t lo, uint64_t hi, uint64_t *out)
{
    return uint_impl(obj, key, lo, hi, true, 0, out);
}

bool jr_uint_opt(jr_object_t *obj, const char *key, uint64_t lo, uint64_t hi, uint64_t def,
                 uint64_t *out)
{
    return uint_impl(obj, key, lo, hi, false, def, out);
}

bool jr_u32_opt(jr_object_t *obj, const char *key, uint32_t lo, uint32_t hi, uint32_t def,
                uint32_t *out)
{
    uint64_t v;
    if (!uint_impl(obj, key, lo, hi, false, def, &v)) {
        return false;
    }
    *out = (uint32_t)v;
    return true;
}

bool jr_string_opt(jr_object_t *obj, const char *key, const char *def, char *buf, size_t size)
{
    const cJSON *item;
    char path[SCN_PATH_MAX];
    char expected[64];
    snprintf(expected, sizeof(expected), "string of at most %zu characters", size - 1);
    if (!lookup(obj, key, &item, path)) {
        return false;
    }
    if (item == NULL) {
        snprintf(buf, size, "%s", def);
        return true;
    }
    if (!cJSON_IsString(item)) {
        fail_at(obj->err, SCN_ERR_TYPE, path, expected, item);
        return false;
    }
    if (strlen(item->valuestring) >= size) {
        fail_at(obj->err, SCN_ERR_RANGE, path, expected, item);
        return false;
    }
    snprintf(buf, size, "%s", item->valuestring);
    return true;
}

bool jr_bool_opt(jr_object_t *obj, const char *key, bool def, bool *out)
{
    const cJSON *item;
    char path[SCN_PATH_MAX];
    if (!lookup(obj, key, &item, path)) {
        return false;
    }
    if (item == NULL) {
        *out = def;
        return true;
    }
    if (!cJSON_IsBool(item)) {
        fail_at(obj->err, SCN_ERR_TYPE, path, "true or false", item);
        return false;
    }
    *out = cJSON_IsTrue(item);
    return true;
}

static void names_text(const char *const *names, size_t n, char *buf, size_t size)
{
    size_t len = (size_t)snprintf(buf, size, "one of");
    for (size_t i = 0; i < n && len < size; i++) {
        len += (size_t)snprintf(buf + len, size - len, "%s \"%s\"", i == 0 ? "" : ",", names[i]);
    }
}

static bool enum_impl(jr_object_t *obj, const char *key, const char *const *names, size_t n,
                      bool required, size_t def, size_t *index)
{
    char expected[SCN_TEXT_MAX];
    names_text(names, n, expected, sizeof(expected));
    const cJSON *item;
    char path[SCN_PATH_MAX];
    if (!lookup_value(obj, key, required, expected, &item, path)) {
        return false;
    }
    if (item == NULL) {
        *index = def;
        return true;
    }
    if (!cJSON_IsString(item)) {
        fail_at(obj->err, SCN_ERR_TYPE, path, expected, item);
        return false;
    }
    for (size_t i = 0; i < n; i++) {
        if (strcmp(item->valuestring, names[i]) == 0) {
            *index = i;
            return true;
        }
    }
    fail_at(obj->err, SCN_ERR_RANGE, path, expected, item);
    return false;
}

bool jr_enum(jr_object_t *obj, const char *key, const char *const *names, size_t n, size_t *index)
{
    return enum_impl(obj, key, names, n, true, 0, index);
}

bool jr_enum_opt(jr_object_t *obj, const char *key, const char *const *names, size_t n, size_t def,
                 size_t *index)
{
    return enum_impl(obj, key, names, n, false, def, index);
}

static void init_array(jr_array_t *arr, const char *path, scn_error_t *err)
{
    arr->json = NULL;
    snprintf(arr->path, sizeof(arr->path), "%s", path);
    arr->err = err;
    arr->size = 0;
}

static void array_text(size_t min_len, size_t max_len, char *buf, size_t size)
{
    snprintf(buf, size, "array of %zu to %zu elements", min_len, max_len);
}

/* item (may be NULL = absent) must be an array of min_len..max_len elements. */
static bool check_array(const cJSON *item, const char *path, size_t min_len, size_t max_len,
                        scn_error_t *err, jr_array_t *arr)
{
    char expected[96];
    array_text(min_len, max_len, expected, sizeof(expected));
    init_array(arr, path, err);
    if (!cJSON_IsArray(item)) {
        fail_at(err, SCN_ERR_TYPE, path, expected, item);
        return false;
    }
    size_t size = (size_t)cJSON_GetArraySize(item);
    if (size < min_len || size > max_len) {
        fail_at(err, SCN_ERR_RANGE, path, expected, item);
        return false;
    }
    arr->json = item;
    arr->size = size;
    return true;
}

static bool array_impl(jr_object_t *obj, const char *key, size_t min_len, size_t max_len,
                       bool required, jr_array_t *arr)
{
    const cJSON *item;
    char path[SCN_PATH_MAX];
    if (!lookup(obj, key, &item, path)) {
        init_array(arr, "", obj->err);
        return false;
    }
    if (item == NULL) {
        init_array(arr, path, obj->err);
        if (required) {
            char expected[96];
            array_text(min_len, max_len, expected, sizeof(expected));
            return missing(obj, path, expected);
        }
        return true;
    }
    return check_array(item, path, min_len, max_len, obj->err, arr);
}

bool jr_array(jr_object_t *obj, const char *key, size_t min_len, size_t max_len, jr_array_t *arr)
{
    return array_impl(obj, key, min_len, max_len, true, arr);
}

bool jr_array_opt(jr_object_t *obj, const char *key, size_t min_len, size_t max_len,
                  jr_array_t *arr)
{
    return array_impl(obj, key, min_len, max_len, false, arr);
}

/* Element i of arr and its path; false after an earlier error. */
static bool element(jr_array_t *arr, size_t i, const cJSON **item, char *path)
{
    if (failed(arr->err) || arr->json == NULL || i >= arr->size) {
        return false;
    }
    join_index(path, arr->path, i);
    *item = cJSON_GetArrayItem(arr->json, (int)i);
    return true;
}

bool jr_array_number(jr_array_t *arr, size_t i, jr_range_t range, double *out)
{
    const cJSON *item;
    char path[SCN_PATH_MAX];
    return element(arr, i, &item, path) && check_number(item, path, range, arr->err, out);
}

bool jr_array_object(jr_array_t *arr, size_t i, jr_object_t *child)
{
    const cJSON *item;
    char path[SCN_PATH_MAX];
    init_object(child, NULL, "", arr->err);
    if (!element(arr, i, &item, path)) {
        return false;
    }
    init_object(child, NULL, path, arr->err);
    if (!cJSON_IsObject(item)) {
        fail_at(arr->err, SCN_ERR_TYPE, path, "object", item);
        return false;
    }
    child->json = item;
    return true;
}

bool jr_array_array(jr_array_t *arr, size_t i, size_t min_len, size_t max_len, jr_array_t *child)
{
    const cJSON *item;
    char path[SCN_PATH_MAX];
    init_array(child, "", arr->err);
    return element(arr, i, &item, path) &&
           check_array(item, path, min_len, max_len, arr->err, child);
}

void jr_fail(jr_object_t *obj, const char *key, scn_status_t code, const char *expected,
             const char *found)
{
    char path[SCN_PATH_MAX];
    join_key(path, obj->path, key);
    scenario_error_set(obj->err, code, path, expected, found);
}

static bool is_known(const jr_object_t *obj, const char *key)
{
    for (size_t i = 0; i < obj->n_known; i++) {
        if (strcmp(obj->known[i], key) == 0) {
            return true;
        }
    }
    return false;
}

bool jr_finish(jr_object_t *obj)
{
    if (failed(obj->err) || obj->json == NULL) {
        return !failed(obj->err);
    }
    for (const cJSON *item = obj->json->child; item != NULL; item = item->next) {
        char path[SCN_PATH_MAX];
        join_key(path, obj->path, item->string);
        if (!is_known(obj, item->string)) {
            char expected[SCN_TEXT_MAX];
            names_text(obj->known, obj->n_known, expected, sizeof(expected));
            scenario_error_set(obj->err, SCN_ERR_UNKNOWN_KEY, path,
                               obj->n_known > 0 ? expected : "no keys here", NULL);
            return false;
        }
        for (const cJSON *later = item->next; later != NULL; later = later->next) {
            if (strcmp(later->string, item->string) == 0) {
                scenario_error_set(obj->err, SCN_ERR_DUPLICATE_KEY, path, "each key once", NULL);
                return false;
            }
        }
    }
    return true;
}
