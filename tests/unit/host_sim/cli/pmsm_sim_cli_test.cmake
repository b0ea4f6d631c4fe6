# Command-line checks of pmsm-sim, run by ctest in CMake script mode:
#   cmake -DPMSM_SIM=<exe> -DSCENARIO=<json> -DWORK_DIR=<dir> -DCASE=<case> -P <this file>
# CASE smoke:        a short run of the scenario exits 0 and writes JSON metrics with
#                    the documented keys and a CSV of the expected length
# CASE bad_scenario: invalid scenarios exit 3 naming the key path on stderr
#                    (format 2: a rejected or unknown firmware key, a format-1
#                    file, a bad inverter.duty_update); a bad command line exits 2
# CASE plot:         --plot writes a PNG (needs the project venv, tools/setup.sh)
# CASE fault:        faults injected through the scenario (a NaN current sample,
#                    an over-current sensor spike) latch the fault at the sample
#                    they appear in, with the PWM off from that very period on
# CASE duty_update:  a short run with inverter.duty_update = half_period (sample-
#                    to-apply delay 1.0 period) drives the motor without a fault
# CASE keys:         pmsm-sim keys lists the firmware keys of the parameter table
#                    (not the plant's values) and the CSV columns
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

function(expect_json_type json type)
  string(JSON actual ERROR_VARIABLE err TYPE "${json}" ${ARGN})
  if(err OR NOT actual STREQUAL type)
    string(REPLACE ";" "." where "${ARGN}")
    message(FATAL_ERROR "metrics JSON: ${where} should be ${type}, is '${actual}' ${err}")
  endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

if(CASE STREQUAL "smoke")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set duration_s=0.2
            --json "${WORK_DIR}/metrics.json" --csv "${WORK_DIR}/trace.csv" --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("pmsm-sim run exited ${rc}: ${err}" rc EQUAL 0)
  file(READ "${WORK_DIR}/metrics.json" json)
  string(JSON name GET "${json}" scenario)
  check("scenario name is '${name}'" name STREQUAL paper001_benchmark_foc)
  string(JSON mode GET "${json}" mode)
  check("mode is '${mode}'" mode STREQUAL speed)
  string(JSON periods GET "${json}" pwm_periods)
  check("0.2 s at 20 kHz should be 4000 periods, got ${periods}" periods EQUAL 4000)
  expect_json_type("${json}" NUMBER metrics rms_tracking_error_rpm)
  expect_json_type("${json}" NUMBER phases profile peak_phase_current_A)
  expect_json_type("${json}" NUMBER phases profile peak_phase_voltage_V)
  expect_json_type("${json}" NUMBER isr_cost mean_s)
  expect_json_type("${json}" NUMBER isr_cost max_s)
  expect_json_type("${json}" ARRAY faults latched)
  # the steady window (6-7 s) and the load steps lie beyond the shortened run
  expect_json_type("${json}" NULL metrics fluctuation_rpm)
  expect_json_type("${json}" NULL metrics fluctuation_rate_percent)
  string(JSON reason GET "${json}" unavailable fluctuation_rpm)
  check("unexpected reason '${reason}'" reason STREQUAL "no sample in the window")
  string(JSON n_steps LENGTH "${json}" load_steps)
  check("expected 3 load steps, got ${n_steps}" n_steps EQUAL 3)
  expect_json_type("${json}" NULL load_steps 0 max_dip_rpm)
  string(JSON reason GET "${json}" load_steps 0 unavailable)
  check("unexpected reason '${reason}'" reason STREQUAL "no sample in the window")
  # 4000 periods, one row every 20 (output.trace_decimation), plus the header
  file(STRINGS "${WORK_DIR}/trace.csv" rows)
  list(LENGTH rows n_rows)
  check("trace.csv has ${n_rows} lines, expected 201" n_rows EQUAL 201)
  list(GET rows 0 header)
  check("unexpected CSV header '${header}'" header MATCHES "^t_s,omega_m_rad_s,")
elseif(CASE STREQUAL "bad_scenario")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set motor.R_ohm=-1 --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("an out-of-range key should exit 3, exited ${rc}" rc EQUAL 3)
  check("stderr lacks the key path: ${err}" err MATCHES "motor\\.R_ohm: out of range")
  file(WRITE "${WORK_DIR}/typo.json" "{\"format_version\": 2, \"duration_s\": 1, \"motr\": {}}")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${WORK_DIR}/typo.json"
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("a scenario without motor should exit 3, exited ${rc}" rc EQUAL 3)
  check("unexpected stderr: ${err}" err MATCHES "typo\\.json: motor: missing required key")
  file(WRITE "${WORK_DIR}/broken.json" "{\n  \"duration_s\": 1x\n}")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${WORK_DIR}/broken.json"
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("malformed JSON should exit 3, exited ${rc}" rc EQUAL 3)
  check("unexpected stderr: ${err}" err MATCHES "broken\\.json:2:18: malformed JSON")
  # format 2: a firmware value mc_config_validate() rejects names its key
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set firmware.foc_pi.speed_bandwidth_rad_s=1000
            --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("a rejected firmware value should exit 3, exited ${rc}" rc EQUAL 3)
  check("unexpected stderr: ${err}" err MATCHES
        "firmware\\.foc_pi\\.speed_bandwidth_rad_s: invalid value: expected values mc_config_validate\\(\\) accepts.*found foc_pi\\.speed_bandwidth_rad_s = 1000")
  # the plant's values are not firmware keys
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set firmware.motor.R_ohm=0.3 --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("firmware.motor should exit 3, exited ${rc}" rc EQUAL 3)
  check("unexpected stderr: ${err}" err MATCHES "firmware\\.motor: unknown key: expected one of \"controller\"")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set firmware.timing.f_pwm_Hz=20000 --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("firmware.timing.f_pwm_Hz should exit 3, exited ${rc}" rc EQUAL 3)
  check("unexpected stderr: ${err}" err MATCHES "firmware\\.timing\\.f_pwm_Hz: unknown key")
  # a format-1 file is refused at format_version with what changed
  file(WRITE "${WORK_DIR}/format1.json"
    "{\"format_version\": 1, \"duration_s\": 1, \"controller\": {\"type\": \"foc_pi\"}}")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${WORK_DIR}/format1.json"
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("a format-1 file should exit 3, exited ${rc}" rc EQUAL 3)
  check("unexpected stderr: ${err}" err MATCHES
        "format1\\.json: format_version: invalid value: expected format_version 2 \\(.*firmware.*found format_version 1")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set inverter.duty_update=quarter_period --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("a bad inverter.duty_update should exit 3, exited ${rc}" rc EQUAL 3)
  check("unexpected stderr: ${err}" err MATCHES
        "inverter\\.duty_update: out of range: expected one of \"next_period\", \"half_period\"")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --frobnicate
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("an unknown option should exit 2, exited ${rc}" rc EQUAL 2)
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --json a.json --json b.json
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("a repeated output option should exit 2, exited ${rc}" rc EQUAL 2)
  check("unexpected stderr: ${err}" err MATCHES "--json given twice")
  execute_process(
    COMMAND "${PMSM_SIM}" keys "${SCENARIO}"
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("keys with an argument should exit 2, exited ${rc}" rc EQUAL 2)
elseif(CASE STREQUAL "plot")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set duration_s=0.2
            --plot "${WORK_DIR}/trace.png" --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("pmsm-sim run --plot exited ${rc}: ${err}" rc EQUAL 0)
  file(READ "${WORK_DIR}/trace.png" signature LIMIT 8 HEX)
  check("trace.png is not a PNG (${signature})" signature STREQUAL 89504e470d0a1a0a)
elseif(CASE STREQUAL "fault")
  # One row per PWM period (20 kHz, 50 us); the injection starts at 0.1 s.
  foreach(injection
      "{\"kind\": \"current_nan\", \"phase\": \"a\", \"t_start_s\": 0.1}|nonfinite|8"
      "{\"kind\": \"current_offset\", \"phase\": \"b\", \"offset_A\": 40, \"t_start_s\": 0.1, \"t_end_s\": 0.1001}|overcurrent|1")
    string(REPLACE "|" ";" parts "${injection}")
    list(GET parts 0 spec)
    list(GET parts 1 fault_name)
    list(GET parts 2 fault_bit)
    execute_process(
      COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set duration_s=0.15
              --set output.trace_decimation=1 --set "fault_injections=[${spec}]"
              --json "${WORK_DIR}/metrics.json" --csv "${WORK_DIR}/trace.csv" --quiet
      RESULT_VARIABLE rc ERROR_VARIABLE err)
    check("pmsm-sim run with ${fault_name} exited ${rc}: ${err}" rc EQUAL 0)
    file(READ "${WORK_DIR}/metrics.json" json)
    string(JSON latched GET "${json}" faults latched 0)
    string(JSON t_fault GET "${json}" faults first_fault_sim_time_s)
    string(JSON final_state GET "${json}" faults final_state)
    check("${fault_name}: latched '${latched}'" latched STREQUAL fault_name)
    check("${fault_name}: first fault at ${t_fault} s, injected at 0.1 s"
          t_fault GREATER_EQUAL 0.09999 AND t_fault LESS 0.10004)
    check("${fault_name}: final state '${final_state}' (latched)" final_state STREQUAL fault)
    # Trace: outputs on before the fault sample; from the fault sample on,
    # outputs off in every period and the fault bit stays latched.
    file(STRINGS "${WORK_DIR}/trace.csv" rows)
    list(GET rows 0 header)
    string(REPLACE "," ";" names "${header}")
    list(FIND names faults col_faults)
    list(FIND names outputs_on col_outputs_on)
    check("trace.csv header lacks faults or outputs_on: ${header}"
          col_faults GREATER 0 AND col_outputs_on GREATER 0)
    list(REMOVE_AT rows 0)
    set(on_before 0)
    set(rows_after 0)
    foreach(row IN LISTS rows)
      string(REPLACE "," ";" cols "${row}")
      list(GET cols 0 t)
      list(GET cols ${col_faults} faults)
      list(GET cols ${col_outputs_on} outputs_on)
      if(t LESS 0.09999)
        if(outputs_on EQUAL 1)
          math(EXPR on_before "${on_before} + 1")
        endif()
      else()
        math(EXPR rows_after "${rows_after} + 1")
        math(EXPR has_bit "${faults} & ${fault_bit}")
        check("${fault_name}: at t = ${t} s outputs_on = ${outputs_on}, faults = ${faults}"
              outputs_on EQUAL 0 AND has_bit EQUAL ${fault_bit})
      endif()
    endforeach()
    check("${fault_name}: the drive never ran before the fault" on_before GREATER 1000)
    check("${fault_name}: ${rows_after} rows after the fault" rows_after GREATER_EQUAL 999)
  endforeach()
elseif(CASE STREQUAL "duty_update")
  # 0.2 s at 20 kHz in speed mode with the duties latched half a period
  # after the sample; the firmware gets the 1.0-period delay from the HAL.
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set duration_s=0.2
            --set inverter.duty_update=half_period
            --json "${WORK_DIR}/metrics.json" --csv "${WORK_DIR}/trace.csv" --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("pmsm-sim run with half_period exited ${rc}: ${err}" rc EQUAL 0)
  file(READ "${WORK_DIR}/metrics.json" json)
  string(JSON periods GET "${json}" pwm_periods)
  check("0.2 s at 20 kHz should be 4000 periods, got ${periods}" periods EQUAL 4000)
  string(JSON n_faults LENGTH "${json}" faults latched)
  check("half_period: faults latched: ${json}" n_faults EQUAL 0)
  expect_json_type("${json}" NUMBER metrics rms_tracking_error_rpm)
elseif(CASE STREQUAL "keys")
  execute_process(
    COMMAND "${PMSM_SIM}" keys
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  check("pmsm-sim keys exited ${rc}: ${err}" rc EQUAL 0)
  foreach(key firmware.controller firmware.estimator firmware.timing.slow_loop_Hz
          firmware.foc_pi.speed_bandwidth_rad_s firmware.idapbc.integral_enabled
          firmware.encoder.pll_bandwidth_rad_s firmware.flux_ii.a1
          firmware.flux_pll.bandwidth_rad_s firmware.eeo.kappa
          firmware.cdobc.poly_order firmware.cdobc.pid)
    string(REPLACE "." "\\." pattern "${key}")
    check("pmsm-sim keys lacks ${key}:\n${out}" out MATCHES "\n  ${pattern} ")
  endforeach()
  check("pmsm-sim keys lists the list names:\n${out}" out MATCHES
        "firmware\\.controller +one of foc_pi \\| idapbc \\| eeo \\| cdobc +default foc_pi")
  foreach(plant_value "firmware\\.motor\\." "firmware\\.timing\\.f_pwm_Hz"
          "firmware\\.encoder\\.counts_per_rev")
    check("pmsm-sim keys lists a plant value (${plant_value}):\n${out}"
          NOT out MATCHES "${plant_value}")
  endforeach()
  check("pmsm-sim keys lacks the CSV columns:\n${out}" out MATCHES "\n  outputs_on +")
else()
  message(FATAL_ERROR "unknown CASE '${CASE}'")
endif()
