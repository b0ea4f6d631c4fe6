/*
 * Validating reader over a cJSON tree.
 *
 * A jr_object_t is a JSON object seen through its key path ("motor",
 * "disturbances.load_torque_Nm"). Getters read one key, check its type,
 * finiteness and range, and record the first failure in the shared
 * scn_error_t with the full key path. After the first error every getter
 * returns false without touching its output, so a mapping function can read
 * a whole section and test the error once at the end.
 *
 * Optional keys take their default when absent. An optional object that is
 * absent yields a child with json == NULL: its optional getters return
 * defaults and its required getters report the missing key by full path.
 *
 * jr_finish() reports the first key of the object that no getter asked for
 * (SCN_ERR_UNKNOWN_KEY, listing the known keys) and repeated keys
 * (SCN_ERR_DUPLICATE_KEY). Call it after the last getter of each object.
 */
#ifndef SIM_JSON_READER_H
#define SIM_JSON_READER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cjson/cJSON.h>

#include "sim/scenario_error.h"

#define JR_MAX_KEYS 64 /* keys a reader may read from one object */

typedef struct {
    const cJSON *json;       /* the object, NULL when an optional one is absent */
    char path[SCN_PATH_MAX]; /* "" for the root */
    scn_error_t *err;
    const char *known[JR_MAX_KEYS];
    size_t n_known;
} jr_object_t;

typedef struct {
    const cJSON *json; /* NULL when an optional array is absent */
    char path[SCN_PATH_MAX];
    scn_error_t *err;
    size_t size;
} jr_array_t;

/* Number range; the ends are included unless marked open. */
typedef struct {
    double lo;
    double hi;
    bool lo_open;
    bool hi_open;
} jr_range_t;

#define JR_CLOSED(lo, hi) ((jr_range_t){ (lo), (hi), false, false })
#define JR_POSITIVE(hi)   ((jr_range_t){ 0.0, (hi), true, false }) /* (0, hi] */
#define JR_ANY_FINITE     ((jr_range_t){ -1e300, 1e300, false, false })

/* The root must be an object. */
bool jr_root(jr_object_t *root, const cJSON *json, scn_error_t *err);

bool jr_ok(const jr_object_t *obj);

/* The raw value of key (NULL if absent, if obj is absent or after an error),
 * to choose between alternative forms. Does not mark the key as known. */
const cJSON *jr_peek(const jr_object_t *obj, const char *key);

/* Child objects. */
bool jr_object(jr_object_t *obj, const char *key, jr_object_t *child);
bool jr_object_opt(jr_object_t *obj, const char *key, jr_object_t *child);

/* Numbers (finite, within range). */
bool jr_number(jr_object_t *obj, const char *key, jr_range_t range, double *out);
bool jr_number_opt(jr_object_t *obj, const char *key, jr_range_t range, double def, double *out);

/* Whole numbers in [lo, hi] (|values| up to 2^53). */
bool jr_uint(jr_object_t *obj, const char *key, uint64_t lo, uint64_t hi, uint64_t *out);
bool jr_uint_opt(jr_object_t *obj, const char *key, uint64_t lo, uint64_t hi, uint64_t def,
                 uint64_t *out);

/* uint32_t convenience form of jr_uint_opt. */
bool jr_u32_opt(jr_object_t *obj, const char *key, uint32_t lo, uint32_t hi, uint32_t def,
                uint32_t *out);

/* A string of at most size - 1 bytes copied into buf (def when absent). */
bool jr_string_opt(jr_object_t *obj, const char *key, const char *def, char *buf, size_t size);

bool jr_bool_opt(jr_object_t *obj, const char *key, bool def, bool *out);

/* A string that must be one of names[0..n-1]; *index receives its position. */
bool jr_enum(jr_object_t *obj, const char *key, const char *const *names, size_t n, size_t *index);
bool jr_enum_opt(jr_object_t *obj, const char *key, const char *const *names, size_t n, size_t def,
                 size_t *index);

/* Arrays with min_len <= size <= max_len; an absent optional array has size 0. */
bool jr_array(jr_object_t *obj, const char *key, size_t min_len, size_t max_len, jr_array_t *arr);
bool jr_array_opt(jr_object_t *obj, const char *key, size_t min_len, size_t max_len,
                  jr_array_t *arr);

/* Elements of an array, with paths "key[i]". */
bool jr_array_number(jr_array_t *arr, size_t i, jr_range_t range, double *out);
bool jr_array_object(jr_array_t *arr, size_t i, jr_object_t *child);
bool jr_array_array(jr_array_t *arr, size_t i, size_t min_len, size_t max_len, jr_array_t *child);

/* Record an error at obj.path + "." + key (key may carry an index,
 * "points[3]"): a rule across keys failed (SCN_ERR_INVALID) or a value has
 * none of the accepted forms (SCN_ERR_TYPE). */
void jr_fail(jr_object_t *obj, const char *key, scn_status_t code, const char *expected,
             const char *found);

/* What a value is, for messages: "string \"abc\"", "-1", "inf", "object". */
void jr_describe(const cJSON *item, char *buf, size_t size);

/* Unknown and duplicate keys of obj (nothing to check when obj is absent). */
bool jr_finish(jr_object_t *obj);

#endif /* SIM_JSON_READER_H */
