/* Scenario top level: document -> validated scenario_t. */
#include "sim/scenario.h"

#include <stdio.h>
#include <string.h>

#include "scenario_sections.h"
#include "sim/scenario_document.h"
#include "sim/scenario_extends.h"

bool scenario_from_json(const cJSON *root_json, scenario_t *out, scn_error_t *err)
{
    jr_object_t root;
    jr_object_t output;
    char description[SCENARIO_DESCRIPTION_MAX];
    uint64_t version;
    memset(out, 0, sizeof(*out));
    plant_config_default(&out->plant);
    mc_config_init_default(&out->controller);
    const bool ok = jr_root(&root, root_json, err) &&
                    jr_uint_opt(&root, "format_version", 1, 1, 1, &version) &&
                    jr_string_opt(&root, "name", "", out->name, sizeof(out->name)) &&
                    jr_string_opt(&root, "description", "", description, sizeof(description)) &&
                    jr_number(&root, "duration_s", JR_POSITIVE(SCENARIO_MAX_DURATION_S),
                              &out->duration_s) &&
                    jr_number_opt(&root, "time_offset_s",
                                  JR_CLOSED(0.0, SCENARIO_MAX_DURATION_S), 0.0,
                                  &out->time_offset_s) &&
                    scenario_read_plant(&root, &out->plant) &&
                    scenario_read_controller(&root, &out->plant, &out->controller) &&
                    scenario_read_reference(&root, &out->reference) &&
                    scenario_read_injections(&root, out->injections, &out->n_injections) &&
                    scenario_read_metrics(&root, out->duration_s, &out->metrics) &&
                    jr_object_opt(&root, "output", &output) &&
                    jr_u32_opt(&output, "trace_decimation", 1, 1000000, 20,
                               &out->trace_decimation) &&
                    jr_finish(&output) && jr_finish(&root);
    if (ok) {
        scenario_apply_time_offset(out);
    }
    return ok;
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
