#!/bin/bash
# Period sweep of the paper 000 regulator (controller eeo): runs
# paper 000 scenarios with the regulator's period Ts = the PWM period at
# 10 us .. 1 ms and prints, per Ts, the time to 1e-3 rad, the largest
# |theta - theta*| over the last second, the peak |v_dq| (drive and paper
# units, paper = sqrt(3/2) x drive), the last-second v_q ripple and the
# faults. Usage (from the repository root):
#   tools/p000_period_sweep.sh BUILD_DIR [SCENARIO.json ...]
# Default scenarios: paper000_eeo_case1.json and paper000_eeo_case2.json.
# Environment: PERIODS_US (default "10 20 50 100 200 500 1000"), PLANT_STEP_US
# (plant substep, default 1), KEEP_DIR (keep the JSON metrics there).
#
# What follows Ts (the rest of each file is unchanged):
# - inverter.f_pwm_Hz = 1 / Ts (the regulator runs in the fast ISR);
# - firmware.timing.slow_loop_Hz = f_pwm / N, the smallest whole N giving at
#   most 2000 Hz (it must divide f_pwm: 1250 Hz at 5 kHz);
# - firmware.current.bandwidth_rad_s, firmware.encoder.pll_bandwidth_rad_s:
#   their defaults (2513, 1000 rad/s) while w Ts <= 0.4, else 0.4 / Ts (the
#   firmware accepts w Ts <= 0.5; the eeo controller uses neither in
#   position mode, but both are designed and validated);
# - the offset calibration: the 25.6 ms of the files rounded to whole
#   periods (n = round(25.6 ms / Ts)), with time_offset_s, duration_s
#   (20 s after it) and firmware.eeo.g3_phase_rad (Omega x the calibration
#   time, Omega = firmware.eeo.g3_omega_rad_s = 1 rad/s in the files)
#   following, so that the profile, the load and the known g3 schedule
#   start with the regulator as in the shipped files;
# - solver.substeps_per_period = Ts / PLANT_STEP_US (a 1 us plant step;
#   the exact integrator of host_sim/plant/plant.h in RUN).
# The peak voltage is taken from the firmware's v_d, v_q commands of every
# period with the outputs on (a CSV trace at full rate, piped, not stored).
set -euo pipefail

build=${1:?usage: tools/p000_period_sweep.sh BUILD_DIR [SCENARIO.json ...]}
shift
sim="$build/host_sim/cli/pmsm-sim"
[ -x "$sim" ] || { echo "p000_period_sweep: no pmsm-sim at $sim" >&2; exit 2; }
if [ $# -eq 0 ]; then
    set -- host_sim/scenarios/paper000_eeo_case1.json host_sim/scenarios/paper000_eeo_case2.json
fi
periods=${PERIODS_US:-10 20 50 100 200 500 1000}
plant_step_us=${PLANT_STEP_US:-1}
omega_g3=1.0 # firmware.eeo.g3_omega_rad_s of the paper 000 files
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# jget FILE PATH: the value at the dotted PATH of pmsm-sim's JSON metrics
# (one key per line, as pmsm-sim writes them); empty if absent.
jget() {
    awk -v want="$2" '
        function path(k) { return (depth > 0 ? stack[depth] "." : "") k }
        {
            line = $0
            gsub(/^[ \t]+/, "", line)
            if (line ~ /^}/) { depth--; next }
            if (match(line, /^"[^"]*":/) == 0) next
            key = substr(line, 2, RLENGTH - 3)
            val = substr(line, RLENGTH + 1)
            gsub(/^[ \t]+|,?[ \t]*$/, "", val)
            if (val == "{") { stack[depth + 1] = path(key); depth++; next }
            if (path(key) == want) { gsub(/^"|"$/, "", val); print val; exit }
        }' "$1"
}

fmt() { # fmt VALUE PRINTF_FORMAT: "-" for empty or null
    if [ -z "$1" ] || [ "$1" = null ]; then printf '%s' "-"; else printf "$2" "$1"; fi
}

printf '%-24s %7s %8s %9s %10s %10s %10s %9s %s\n' scenario "Ts_us" "f_kHz" "t_1e-3_s" \
    "last_1s_rad" "peak_v_drv" "peak_v_pap" "ripple_V" faults
for scen in "$@"; do
    name=$(basename "$scen" .json)
    for ts_us in $periods; do
        read -r f_hz slow_hz cb_rad_s pll_rad_s calib_s offset_s dur_s phase_rad substeps < <(
            awk -v ts_us="$ts_us" -v step_us="$plant_step_us" -v om="$omega_g3" 'BEGIN {
                ts = ts_us * 1e-6; f = 1e6 / ts_us
                nd = int((f + 1999) / 2000); while (f % nd) nd++; slow = f / nd
                cb = (2513 * ts <= 0.4) ? 2513 : 0.4 / ts
                pll = (1000 * ts <= 0.4) ? 1000 : 0.4 / ts
                n = int(0.0256 / ts + 0.5); calib = n * ts
                ns = int(ts_us / step_us + 0.5); if (ns < 1) ns = 1
                printf "%.10g %.10g %.10g %.10g %.10g %.10g %.10g %.10g %d\n",
                    f, slow, cb, pll, calib, calib, 20 + calib, om * calib, ns }')
        json="$work/$name.$ts_us.json"
        status=0
        vline=$("$sim" run "$scen" --quiet --json "$json" --csv /dev/stdout \
            --set "inverter.f_pwm_Hz=$f_hz" \
            --set "firmware.timing.slow_loop_Hz=$slow_hz" \
            --set "firmware.timing.calib_time_s=$calib_s" \
            --set "firmware.current.bandwidth_rad_s=$cb_rad_s" \
            --set "firmware.encoder.pll_bandwidth_rad_s=$pll_rad_s" \
            --set "firmware.eeo.g3_phase_rad=$phase_rad" \
            --set "time_offset_s=$offset_s" \
            --set "duration_s=$dur_s" \
            --set "solver.substeps_per_period=$substeps" \
            --set "output.trace_decimation=1" |
            awk -F, -v t0="$(awk -v o="$offset_s" 'BEGIN { print o + 19 }')" \
                -v t1="$(awk -v o="$offset_s" 'BEGIN { print o + 20 }')" '
                NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
                $c["outputs_on"] == 1 {
                    v = sqrt($c["v_d_ref_V"]^2 + $c["v_q_ref_V"]^2)
                    if (v > peak) peak = v
                    if ($c["t_s"] >= t0 && $c["t_s"] <= t1) {
                        q = $c["v_q_ref_V"]
                        if (!seen || q < qmin) qmin = q
                        if (!seen || q > qmax) qmax = q
                        seen = 1
                    }
                }
                END { printf "%.6g %.6g\n", peak, seen ? qmax - qmin : -1 }') || status=$?
        if [ "$status" -ne 0 ] || [ ! -s "$json" ]; then
            printf '%-24s %7s %8s  pmsm-sim exited %s\n' "$name" "$ts_us" "$f_hz" "$status"
            continue
        fi
        [ -n "${KEEP_DIR:-}" ] && cp "$json" "$KEEP_DIR/"
        read -r peak_drv ripple_drv <<<"$vline"
        t_set=$(jget "$json" metrics.settling_time_s)
        [ -z "$t_set" ] && t_set="never($(jget "$json" unavailable.settling_time_s | cut -c1-30))"
        e_last=$(jget "$json" windows.last_second.max_abs_error_rad)
        faults=$(grep -A3 '"latched":' "$json" | tr -d ' \t\n' | sed 's/.*"latched":\[\([^]]*\)\].*/\1/')
        t_fault=$(jget "$json" faults.first_fault_profile_time_s)
        [ -z "$faults" ] && faults=none || faults="$faults@$(fmt "$t_fault" '%.4g')s"
        printf '%-24s %7s %8s %9s %10s %10s %10s %9s %s\n' "$name" "$ts_us" \
            "$(awk -v f="$f_hz" 'BEGIN { printf "%g", f / 1000 }')" \
            "$(fmt "$t_set" '%.4g')" "$(fmt "$e_last" '%.3g')" \
            "$(fmt "$peak_drv" '%.4g')" \
            "$(awk -v v="$peak_drv" 'BEGIN { printf "%.4g", v * sqrt(1.5) }')" \
            "$(awk -v v="$ripple_drv" 'BEGIN { printf "%.3g", v * sqrt(1.5) }')" "$faults"
    done
done
