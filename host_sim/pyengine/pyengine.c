/* The simulated drive as a shared library (pyengine.h). */
#include "pyengine.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mc/can_node.h"
#include "sim/scenario.h"
#include "sim_engine.h"

struct pe {
    scenario_t scn;
    sim_engine_t engine;
};

pe_t *pe_open(const char *scenario_file, const char *const *set, int n_set, uint32_t node_id,
              double timeout_s, char *err, int err_len)
{
    if (err_len > 0) {
        err[0] = '\0';
    }
    pe_t *h = calloc(1, sizeof *h);
    if (h == NULL || n_set < 0) {
        (void)snprintf(err, (size_t)err_len, "pe_open: %s",
                       h == NULL ? "out of memory" : "negative override count");
        free(h);
        return NULL;
    }
    scn_error_t e;
    if (!scenario_load(scenario_file, set, (size_t)n_set, &h->scn, &e)) {
        scenario_error_format(&e, err, (size_t)err_len);
        free(h);
        return NULL;
    }
    int st = sim_engine_init(&h->engine, &h->scn.plant, &h->scn.firmware);
    for (size_t i = 0; st == SIM_ENGINE_OK && i < h->scn.n_injections; ++i) {
        st = sim_engine_add_injection(&h->engine, &h->scn.injections[i]);
    }
    mc_can_node_config_t cfg;
    mc_can_node_config_default(&cfg);
    cfg.node_id = node_id;
    cfg.timeout_s = (float)timeout_s;
    if (st == SIM_ENGINE_OK) {
        st = sim_engine_can_attach(&h->engine, &cfg);
    }
    if (st != SIM_ENGINE_OK) {
        (void)snprintf(err, (size_t)err_len, "pe_open: %s: engine: %s", scenario_file,
                       sim_engine_message(&h->engine));
        free(h);
        return NULL;
    }
    return h;
}

int pe_step(pe_t *h, int n)
{
    const mc_command_t ignored = { 0 }; /* the CAN node commands */
    for (int k = 0; k < n; ++k) {
        const int st = sim_engine_step(&h->engine, &ignored);
        if (st != SIM_ENGINE_OK) {
            return st;
        }
    }
    return 0;
}

double pe_time_s(const pe_t *h)
{
    return sim_engine_time_s(&h->engine);
}

double pe_speed_rad_s(const pe_t *h)
{
    return sim_engine_last(&h->engine)->plant.omega_m_rad_s;
}

int pe_deliver(pe_t *h, uint32_t id, uint32_t dlc, const uint8_t *data, int flags)
{
    hal_can_frame_t f = { .id = id,
                          .extended = (flags & PE_FRAME_EXTENDED) != 0,
                          .rtr = (flags & PE_FRAME_RTR) != 0,
                          .dlc = (uint8_t)dlc };
    if (dlc > HAL_CAN_MAX_DLC || !hal_can_frame_valid(&f)) {
        return -1;
    }
    memcpy(f.data, data, dlc);
    return sim_engine_can_deliver(&h->engine, &f) ? 1 : 0;
}

int pe_collect(pe_t *h, uint32_t *id, uint32_t *dlc, uint8_t *data, int *flags)
{
    hal_can_frame_t f;
    if (!sim_engine_can_collect(&h->engine, &f)) {
        return 0;
    }
    *id = f.id;
    *dlc = f.dlc;
    memcpy(data, f.data, HAL_CAN_MAX_DLC);
    *flags = (f.extended ? PE_FRAME_EXTENDED : 0) | (f.rtr ? PE_FRAME_RTR : 0);
    return 1;
}

void pe_close(pe_t *h)
{
    free(h);
}
