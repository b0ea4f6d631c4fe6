/* Scenario top level: document -> validated scenario_t. */
#include "sim/scenario.h"

#include <stdio.h>
#include <string.h>

#include "scenario_sections.h"
#include "sim/scenario_document.h"
#include "sim/scenario_extends.h"

/* Format 2 only; a format-1 file gets a message saying what changed. */
static bool read_format_version(jr_object_t *root)
{
    const cJSON *v = jr_peek(root, "format_version");
    const bool old = (v != NULL && cJSON_IsNumber(v) && v->valuedouble == 1.0) ||
                     (v == NULL && jr_peek(root, "controller") != NULL);
    if (old) {
        jr_fail(root, "format_version", SCN_ERR_INVALID,
                "format_version 2 (format 1 is no longer read: its \"controller\" section is "
                "now \"firmware\" with the keys grouped by block, e.g. "
                "controller.current_bandwidth_rad_s -> firmware.current.bandwidth_rad_s, "
                "controller.type -> firmware.controller, controller.angle_source -> "
                "firmware.estimator; profile keys freq_hz, cutoff_hz -> freq_Hz, cutoff_Hz; "
                "see host_sim/scenarios/README.md, \"Changes from format 1\")",
                v != NULL ? "format_version 1" : "a \"controller\" section");
        return false;
    }
    uint64_t version;
    return jr_uint(root, "format_version", SCENARIO_FORMAT_VERSION, SCENARIO_FORMAT_VERSION,
                   &version);
}

bool scenario_from_json(const cJSON *root_json, scenario_t *out, scn_error_t *err)
{
    jr_object_t root;
    jr_object_t output;
    char description[SCENARIO_DESCRIPTION_MAX];
    memset(out, 0, sizeof(*out));
    plant_config_default(&out->plant);
    mc_config_init_default(&out->firmware);
    const bool ok =
        jr_root(&root, root_json, err) && read_format_version(&root) &&
        jr_string_opt(&root, "name", "", out->name, sizeof(out->name)) &&
        jr_string_opt(&root, "description", "", description, sizeof(description)) &&
        jr_number(&root, "duration_s", JR_POSITIVE(SCENARIO_MAX_DURATION_S), &out->duration_s) &&
        jr_number_opt(&root, "time_offset_s", JR_CLOSED(0.0, SCENARIO_MAX_DURATION_S), 0.0,
                      &out->time_offset_s) &&
        scenario_read_plant(&root, &out->plant) &&
        scenario_read_firmware(&root, &out->plant, &out->firmware) &&
        scenario_read_reference(&root, &out->reference) &&
        scenario_read_injections(&root, out->injections, &out->n_injections) &&
        scenario_read_metrics(&root, out->duration_s, &out->metrics) &&
        jr_object_opt(&root, "output", &output) &&
        jr_u32_opt(&output, "trace_decimation", 1, 1000000, 20, &out->trace_decimation) &&
        jr_finish(&output) && jr_finish(&root);
    if (!ok) {
        return false;
    }
    scenario_apply_time_offset(out);
    return scenario_check_bounds(&root, out);
}

/* "dir/p001_foc.json" -> "p001_foc" when the scenario has no name. */
static void default_name(scenario_t *s, const char *file)
{
    if (s->name[0] != '\0' || file == NULL) {
        return;
    }
    const char *base = strrchr(file, '/');
    base = base != NULL ? base + 1 : file;
    size_t n = strcspn(base, ".");
    snprintf(s->name, sizeof(s->name), "%.*s", (int)n, base);
}

static bool finish_load(cJSON *doc, const char *file, const char *const *overrides,
                        size_t n_overrides, scenario_t *out, scn_error_t *err)
{
    doc = doc != NULL ? scenario_extends_resolve(doc, file, err) : NULL;
    bool ok = doc != NULL;
    for (size_t i = 0; ok && i < n_overrides; i++) {
        ok = scenario_document_set(doc, overrides[i], err);
    }
    ok = ok && scenario_from_json(doc, out, err);
    if (ok) {
        default_name(out, file);
    }
    cJSON_Delete(doc);
    return ok;
}

bool scenario_load(const char *file, const char *const *overrides, size_t n_overrides,
                   scenario_t *out, scn_error_t *err)
{
    scenario_error_clear(err);
    cJSON *doc = scenario_document_load(file, err);
    return finish_load(doc, file, overrides, n_overrides, out, err);
}

bool scenario_load_text(const char *text, const char *file, const char *const *overrides,
                        size_t n_overrides, scenario_t *out, scn_error_t *err)
{
    scenario_error_clear(err);
    cJSON *doc = scenario_document_parse(text, file, err);
    return finish_load(doc, file, overrides, n_overrides, out, err);
}
