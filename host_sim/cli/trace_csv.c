/* CSV trace rows: the column table (trace_csv.h). */
#include "trace_csv.h"

#include "angle_diff.h"

typedef double (*column_value_t)(const sim_trace_sample_t *smp);

typedef struct {
    const char *name; /* header name, unit in it */
    const char *meaning;
    int digits; /* significant digits (%.*g); 0: an integer */
    column_value_t value;
} column_t;

#define TRUE_(field) smp->plant.field
#define FW(field)    (double)smp->fw.field

static double t_s(const sim_trace_sample_t *smp)
{
    return TRUE_(t_s);
}
static double omega(const sim_trace_sample_t *smp)
{
    return TRUE_(omega_m_rad_s);
}
static double omega_est(const sim_trace_sample_t *smp)
{
    return FW(omega_m_rad_s);
}
static double omega_ref(const sim_trace_sample_t *smp)
{
    return FW(omega_m_ref_rad_s);
}
static double theta(const sim_trace_sample_t *smp)
{
    return TRUE_(theta_m_rad);
}
static double theta_ref(const sim_trace_sample_t *smp)
{
    return FW(theta_m_ref_rad);
}
static double angle_error(const sim_trace_sample_t *smp)
{
    return angle_diff_rad(FW(theta_e_rad), TRUE_(theta_e_rad));
}
static double i_d(const sim_trace_sample_t *smp)
{
    return TRUE_(i_d_A);
}
static double i_q(const sim_trace_sample_t *smp)
{
    return TRUE_(i_q_A);
}
static double i_d_ref(const sim_trace_sample_t *smp)
{
    return FW(i_d_ref_A);
}
static double i_q_ref(const sim_trace_sample_t *smp)
{
    return FW(i_q_ref_A);
}
static double i_a(const sim_trace_sample_t *smp)
{
    return TRUE_(i_abc_A[0]);
}
static double i_b(const sim_trace_sample_t *smp)
{
    return TRUE_(i_abc_A[1]);
}
static double i_c(const sim_trace_sample_t *smp)
{
    return TRUE_(i_abc_A[2]);
}
static double v_d_ref(const sim_trace_sample_t *smp)
{
    return FW(v_d_V);
}
static double v_q_ref(const sim_trace_sample_t *smp)
{
    return FW(v_q_V);
}
static double v_a(const sim_trace_sample_t *smp)
{
    return TRUE_(v_abc_V[0]);
}
static double v_b(const sim_trace_sample_t *smp)
{
    return TRUE_(v_abc_V[1]);
}
static double v_c(const sim_trace_sample_t *smp)
{
    return TRUE_(v_abc_V[2]);
}
static double v_dc(const sim_trace_sample_t *smp)
{
    return TRUE_(v_dc_V);
}
static double tau_e(const sim_trace_sample_t *smp)
{
    return TRUE_(tau_e_Nm);
}
static double tau_load(const sim_trace_sample_t *smp)
{
    return TRUE_(tau_load_Nm);
}
static double tau_load_est(const sim_trace_sample_t *smp)
{
    return FW(tau_L_hat_Nm);
}
static double state(const sim_trace_sample_t *smp)
{
    return (double)smp->fw.state;
}
static double faults(const sim_trace_sample_t *smp)
{
    return FW(faults_latched);
}
static double outputs_on(const sim_trace_sample_t *smp)
{
    return smp->outputs_applied ? 1.0 : 0.0;
}

static const column_t columns[] = {
    { "t_s", "sampling instant t_k", 9, t_s },
    { "omega_m_rad_s", "true mechanical speed", 7, omega },
    { "omega_m_est_rad_s", "firmware speed estimate", 7, omega_est },
    { "omega_m_ref_rad_s", "firmware speed reference", 7, omega_ref },
    { "theta_m_rad", "true mechanical position (multi-turn)", 9, theta },
    { "theta_m_ref_rad", "commanded position", 9, theta_ref },
    { "angle_error_e_rad", "firmware theta_e minus true theta_e, wrapped to [-pi, pi)", 6,
      angle_error },
    { "i_d_A", "true d current", 6, i_d },
    { "i_q_A", "true q current", 6, i_q },
    { "i_d_ref_A", "firmware d current reference", 6, i_d_ref },
    { "i_q_ref_A", "firmware q current reference", 6, i_q_ref },
    { "i_a_A", "true phase-a current", 6, i_a },
    { "i_b_A", "true phase-b current", 6, i_b },
    { "i_c_A", "true phase-c current", 6, i_c },
    { "v_d_ref_V", "firmware d voltage command (after the limit)", 6, v_d_ref },
    { "v_q_ref_V", "firmware q voltage command (after the limit)", 6, v_q_ref },
    { "v_a_V", "plant phase-a voltage, mean over the previous period", 6, v_a },
    { "v_b_V", "plant phase-b voltage, mean over the previous period", 6, v_b },
    { "v_c_V", "plant phase-c voltage, mean over the previous period", 6, v_c },
    { "v_dc_V", "true bus voltage", 6, v_dc },
    { "tau_e_Nm", "true electromagnetic torque", 6, tau_e },
    { "tau_load_Nm", "true load torque", 6, tau_load },
    { "tau_load_est_Nm", "firmware load-torque estimate (0 without one)", 6, tau_load_est },
    { "state", "firmware state (mc_state_t)", 0, state },
    { "faults", "latched firmware faults (mc_fault_t bits)", 0, faults },
    { "outputs_on", "1 if the inverter switched in the period from t_s, else 0", 0, outputs_on },
};

#define N_COLUMNS (sizeof(columns) / sizeof(columns[0]))

size_t trace_csv_column_count(void)
{
    return N_COLUMNS;
}

const char *trace_csv_column_name(size_t i)
{
    return columns[i].name;
}

const char *trace_csv_column_meaning(size_t i)
{
    return columns[i].meaning;
}

void trace_csv_header(FILE *f)
{
    for (size_t i = 0; i < N_COLUMNS; i++) {
        fprintf(f, "%s%s", i > 0 ? "," : "", columns[i].name);
    }
    fputc('\n', f);
}

/* Column c's text for v (snprintf style). */
static int format_value(char *buf, size_t size, const column_t *c, double v)
{
    return c->digits == 0 ? snprintf(buf, size, "%.0f", v)
                          : snprintf(buf, size, "%.*g", c->digits, v);
}

void trace_csv_row(FILE *f, const sim_trace_sample_t *smp)
{
    char text[64];
    for (size_t i = 0; i < N_COLUMNS; i++) {
        const column_t *c = &columns[i];
        format_value(text, sizeof(text), c, c->value(smp));
        if (i > 0) {
            fputc(',', f);
        }
        fputs(text, f);
    }
    fputc('\n', f);
}

size_t trace_csv_row_bytes(void)
{
    /* every number at its full precision, an integer column one digit */
    const double full_precision = -1.0 - 1.0 / 3.0;
    size_t bytes = N_COLUMNS; /* the commas and the newline */
    for (size_t i = 0; i < N_COLUMNS; i++) {
        const column_t *c = &columns[i];
        bytes += (size_t)format_value(NULL, 0, c, c->digits == 0 ? 1.0 : full_precision);
    }
    return bytes;
}
