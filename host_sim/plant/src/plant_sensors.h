/* Internal to sim_plant: the encoder's turn count (plant_sensors.c). */
#ifndef SIM_PLANT_SENSORS_H
#define SIM_PLANT_SENSORS_H

#include <stdint.h>

/* floor((theta_m + offset) / 2 pi), the turn the encoder is in, modulo
 * 2^53 (exact in a double, so any two neighbouring turns differ): the
 * index pulse only needs to see the turn change. Defined for every finite
 * angle, however large (a diverged plant, a huge load), where converting
 * the turn itself to int64_t would overflow; 0 for a non-finite angle. */
int64_t plant_encoder_turn(double theta_m_rad, double offset_rad);

#endif /* SIM_PLANT_SENSORS_H */
