#include <math.h>

#include "plant.h"
#include "plant_frames.h"
#include "plant_sensors.h"
#include "sim_rng.h"

#define TURN_MODULUS 9007199254740992.0 /* 2^53 */

/* Standard normal draw (Box-Muller on the plant's PRNG; pairs cached). */
static double gaussian(plant_t *p)
{
    if (p->have_spare_gauss) {
        p->have_spare_gauss = false;
        return p->spare_gauss;
    }
    /* u1 in (0, 1] so log() is finite */
    const double u1 = 1.0 - sim_rng_unit(sim_rng_next_u64(&p->rng_state));
    const double u2 = sim_rng_unit(sim_rng_next_u64(&p->rng_state));
    const double r = sqrt(-2.0 * log(u1));
    p->spare_gauss = r * sin(PLANT_TWO_PI * u2);
    p->have_spare_gauss = true;
    return r * cos(PLANT_TWO_PI * u2);
}

/* Mid-tread quantiser with codes in [code_min, code_max]. */
static double quantise(double v, double lsb, double code_min, double code_max)
{
    double code = nearbyint(v / lsb);
    code = code < code_min ? code_min : (code > code_max ? code_max : code);
    return code * lsb;
}

static double measure_current(plant_t *p, int x, double i_true_A)
{
    const plant_current_sensor_t *c = &p->cfg.sensors.current;
    double v = c->gain[x] * i_true_A + c->offset_A[x];
    if (c->noise_rms_A > 0.0) {
        v += c->noise_rms_A * gaussian(p);
    }
    if (c->adc_bits == 0u) {
        return v;
    }
    const double half_codes = ldexp(1.0, (int)c->adc_bits - 1);
    return quantise(v, c->full_scale_A / half_codes, -half_codes, half_codes - 1.0);
}

static double measure_vdc(plant_t *p, double v_dc_V)
{
    const plant_vdc_sensor_t *s = &p->cfg.sensors.vdc;
    double v = s->gain * v_dc_V + s->offset_V;
    if (s->noise_rms_V > 0.0) {
        v += s->noise_rms_V * gaussian(p);
    }
    if (s->adc_bits == 0u) {
        return v;
    }
    const double codes = ldexp(1.0, (int)s->adc_bits);
    return quantise(v, s->full_scale_V / codes, 0.0, codes - 1.0);
}

int64_t plant_encoder_turn(double theta_m_rad, double offset_rad)
{
    const double turns = floor((theta_m_rad + offset_rad) / PLANT_TWO_PI);
    return isfinite(turns) ? (int64_t)fmod(turns, TURN_MODULUS) : 0;
}

/* The time since the count's last edge, from the fraction of a count the
 * shaft has turned past it (frac in [0, 1) of the count, counting up) at
 * the speed of the sample (counts per s): the edge below when turning
 * forward, the one above when turning back. Exact at constant speed (a
 * count lasts 12 us at 500 rpm with 10000 counts per turn); no motion:
 * INFINITY. */
static double edge_age_s(double frac, double counts_per_s)
{
    const double past = (counts_per_s > 0.0) ? frac : (counts_per_s < 0.0) ? 1.0 - frac : INFINITY;
    return past / fabs(counts_per_s);
}

void plant_sample(plant_t *p, plant_measurement_t *m)
{
    const plant_true_state_t *v = &p->view;
    m->t_s = v->t_s;
    for (int x = 0; x < 3; ++x) {
        m->i_abc_A[x] = measure_current(p, x, v->i_abc_A[x]);
    }
    m->v_dc_V = measure_vdc(p, v->v_dc_V);

    const plant_encoder_t *enc = &p->cfg.sensors.encoder;
    m->encoder_count = 0u;
    m->encoder_edge_age_s = INFINITY;
    m->encoder_index = false;
    const double revs = (v->theta_m_rad + enc->offset_rad) / PLANT_TWO_PI;
    /* no count for a non-finite angle (a diverged plant state) */
    if (enc->lines > 0u && isfinite(revs)) {
        const double cpr = 4.0 * (double)enc->lines;
        /* the fraction of a turn is in [0, 1): the count fits cpr <= 2^30 */
        const double counts = (revs - floor(revs)) * cpr;
        uint32_t count = (uint32_t)floor(counts);
        m->encoder_count = count >= (uint32_t)cpr ? 0u : count; /* rounding at 1.0 */
        m->encoder_edge_age_s =
            edge_age_s(counts - floor(counts), v->omega_m_rad_s * cpr / PLANT_TWO_PI);
        const int64_t turn = plant_encoder_turn(v->theta_m_rad, enc->offset_rad);
        m->encoder_index = (turn != p->encoder_turns);
        p->encoder_turns = turn;
    }
}
