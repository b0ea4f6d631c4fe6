/* Private helpers shared by the files of firmware/app. */
#ifndef MC_APP_INTERNAL_H
#define MC_APP_INTERNAL_H

#include "mc/app.h"

/* Publish a telemetry snapshot (sequence counter odd while writing).
 * Called from init and at the end of the fast ISR. */
void mc_app_publish_telemetry(mc_app_t *app, const mc_telemetry_t *t);

#endif /* MC_APP_INTERNAL_H */
