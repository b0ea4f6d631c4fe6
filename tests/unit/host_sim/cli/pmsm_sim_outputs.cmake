# Outputs of pmsm-sim run checked before the run, and never left half
# written, run by ctest in CMake script mode:
#   cmake -DPMSM_SIM=<exe> -DSCENARIO=<json> -DWORK_DIR=<dir> -DCASE=<case> -P <this file>
# CASE before_run:  a missing directory (--csv, --json, --plot), an output
#                   that is the scenario file, two outputs naming one file and
#                   a missing or broken plotting environment fail with exit 4
#                   before anything runs: the scenario is set to 36000 s, so
#                   a run started by mistake would time the test out; no file
#                   is created and the scenario file is unchanged
# CASE no_partial:  a failure after the run (the plot script fails) leaves the
#                   earlier contents of --csv and --json targets as they were
#                   and no staging directory; a success replaces them; a long
#                   run stopped by SIGTERM leaves no output and no staging
# CASE estimate:    --dry-run states periods, CSV rows and bytes from the
#                   scenario, the wall time extrapolated from the pilot run,
#                   and writes nothing; a run no longer than the pilot is not
#                   timed; the size per row is within +-20 % of what a real
#                   run writes; a long run states the estimate on stderr
#                   before it starts
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
file(COPY_FILE "${SCENARIO}" "${WORK_DIR}/scenario.json")
set(scn "${WORK_DIR}/scenario.json")

# run_sim(<rc var> <stderr var> args...): pmsm-sim run on the copy.
function(run_sim rc_var err_var)
  execute_process(COMMAND "${PMSM_SIM}" run "${scn}" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${rc_var} "${rc}" PARENT_SCOPE)
  set(${err_var} "${err}" PARENT_SCOPE)
  set(last_stdout "${out}" PARENT_SCOPE)
endfunction()

# Nothing but the scenario (and files the case made itself) in WORK_DIR.
function(expect_only_in_work_dir)
  file(GLOB present RELATIVE "${WORK_DIR}" "${WORK_DIR}/*" "${WORK_DIR}/.*")
  list(SORT present)
  list(JOIN present "," present)
  set(expected ${ARGN})
  list(SORT expected)
  list(JOIN expected "," expected)
  check("files in the work directory: '${present}', expected '${expected}'"
        present STREQUAL expected)
endfunction()

if(CASE STREQUAL "before_run")
  file(SHA256 "${scn}" scenario_hash)
  set(long --set duration_s=36000 --quiet)
  foreach(option --csv --json --plot)
    run_sim(rc err ${long} ${option} "${WORK_DIR}/missing/out.file")
    check("${option} into a missing directory exited ${rc}, expected 4: ${err}" rc EQUAL 4)
    check("unexpected stderr: ${err}" err MATCHES
          "${option} [^:]*/missing/out\\.file: the directory [^ ]*/missing does not exist")
  endforeach()
  foreach(option --csv --json --plot)
    run_sim(rc err ${long} ${option} "${scn}")
    check("${option} onto the scenario exited ${rc}, expected 4: ${err}" rc EQUAL 4)
    check("unexpected stderr: ${err}" err MATCHES "is the scenario file")
  endforeach()
  get_filename_component(work_name "${WORK_DIR}" NAME)
  run_sim(rc err ${long} --csv "${WORK_DIR}/a.out" --json "${WORK_DIR}/../${work_name}/a.out")
  check("--csv and --json on one file exited ${rc}, expected 4: ${err}" rc EQUAL 4)
  check("unexpected stderr: ${err}" err MATCHES "--csv and --json name the same file")
  # the plotting environment: a Python that does not exist, and a plot
  # script whose --check fails (as with a venv that lacks matplotlib)
  set(ENV{PMSM_SIM_PYTHON} "${WORK_DIR}/no-python")
  run_sim(rc err ${long} --csv "${WORK_DIR}/t.csv" --plot "${WORK_DIR}/t.png")
  check("a missing Python exited ${rc}, expected 4: ${err}" rc EQUAL 4)
  check("unexpected stderr: ${err}" err MATCHES "no Python at [^ ]*/no-python")
  unset(ENV{PMSM_SIM_PYTHON})
  find_program(SH sh REQUIRED)
  file(WRITE "${WORK_DIR}/env/python" "#!${SH}\nexit 3\n")
  file(CHMOD "${WORK_DIR}/env/python" PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
  set(ENV{PMSM_SIM_PYTHON} "${WORK_DIR}/env/python")
  run_sim(rc err ${long} --json "${WORK_DIR}/m.json" --plot "${WORK_DIR}/t.png")
  check("a failing environment check exited ${rc}, expected 4: ${err}" rc EQUAL 4)
  check("unexpected stderr: ${err}" err MATCHES "the plotting environment is not usable")
  unset(ENV{PMSM_SIM_PYTHON})
  expect_only_in_work_dir(env scenario.json)
  file(SHA256 "${scn}" hash_after)
  check("the scenario file changed" hash_after STREQUAL scenario_hash)
elseif(CASE STREQUAL "no_partial")
  file(WRITE "${WORK_DIR}/t.csv" "earlier trace\n")
  file(WRITE "${WORK_DIR}/m.json" "{\"earlier\": true}\n")
  # a plot script that passes the environment check but fails to plot
  file(WRITE "${WORK_DIR}/fail_plot.py"
       "import sys\nsys.exit(0 if '--check' in sys.argv else 5)\n")
  find_program(PYTHON3 python3 REQUIRED)
  set(ENV{PMSM_SIM_PYTHON} "${PYTHON3}")
  set(ENV{PMSM_SIM_PLOT_SCRIPT} "${WORK_DIR}/fail_plot.py")
  run_sim(rc err --set duration_s=0.05 --quiet --csv "${WORK_DIR}/t.csv"
          --json "${WORK_DIR}/m.json" --plot "${WORK_DIR}/t.png")
  check("a failing plot exited ${rc}, expected 1: ${err}" rc EQUAL 1)
  check("unexpected stderr: ${err}" err MATCHES "the plot script [^ ]*fail_plot\\.py failed")
  file(READ "${WORK_DIR}/t.csv" csv)
  file(READ "${WORK_DIR}/m.json" json)
  check("the earlier CSV was replaced: ${csv}" csv STREQUAL "earlier trace\n")
  check("the earlier JSON was replaced: ${json}" json STREQUAL "{\"earlier\": true}\n")
  expect_only_in_work_dir(scenario.json fail_plot.py m.json t.csv)
  unset(ENV{PMSM_SIM_PYTHON})
  unset(ENV{PMSM_SIM_PLOT_SCRIPT})
  # success: the targets are replaced, the staging is gone
  run_sim(rc err --set duration_s=0.05 --quiet --csv "${WORK_DIR}/t.csv"
          --json "${WORK_DIR}/m.json")
  check("pmsm-sim run exited ${rc}: ${err}" rc EQUAL 0)
  file(STRINGS "${WORK_DIR}/t.csv" rows)
  list(GET rows 0 header)
  check("t.csv was not replaced: ${header}" header MATCHES "^t_s,")
  file(READ "${WORK_DIR}/m.json" json)
  string(JSON periods GET "${json}" pwm_periods)
  check("m.json was not replaced (${periods} periods)" periods GREATER 0)
  expect_only_in_work_dir(scenario.json fail_plot.py m.json t.csv)
  # a long run stopped by SIGTERM (after it stated its estimate) leaves
  # neither its outputs nor their staging, and ends by that signal
  find_program(TIMEOUT timeout REQUIRED)
  execute_process(COMMAND "${TIMEOUT}" -s TERM 3 "${PMSM_SIM}" run "${scn}" --set duration_s=36000
                          --quiet --csv "${WORK_DIR}/long.csv" --json "${WORK_DIR}/long.json"
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("the stopped run: timeout exited ${rc}, expected 124 (timed out): ${err}" rc EQUAL 124)
  check("unexpected stderr: ${err}" err MATCHES
        "^pmsm-sim: a long run: [^\n]*\npmsm-sim: error: run stopped by a signal at t = ")
  expect_only_in_work_dir(scenario.json fail_plot.py m.json t.csv)
elseif(CASE STREQUAL "estimate")
  # 36000 s at 100 kHz, one CSV row every 20 periods: 3.6e9 periods, 1.8e8 rows
  run_sim(rc err --set duration_s=36000 --set inverter.f_pwm_Hz=100000
          --set output.trace_decimation=20 --csv "${WORK_DIR}/big.csv" --dry-run)
  check("--dry-run exited ${rc}: ${err}" rc EQUAL 0)
  set(est "${last_stdout}")
  check("no periods in the estimate: ${est}" est MATCHES
        "36000 s simulated = 3\\.6e\\+09 PWM periods at 100 kHz")
  if(NOT est MATCHES "CSV trace 1\\.8e\\+08 rows x ([0-9]+) bytes = about ([0-9.]+) GB")
    message(FATAL_ERROR "no CSV in the estimate: ${est}")
  endif()
  set(row_bytes "${CMAKE_MATCH_1}")
  set(gb "${CMAKE_MATCH_2}")
  if(NOT est MATCHES "wall time about ([0-9.]+) h \\(([0-9.]+) us per period, measured on a pilot run of its first 10000 periods\\)")
    message(FATAL_ERROR "no measured wall time in the estimate: ${est}")
  endif()
  # 3.6e9 periods x U us = 3600 U s = U h
  check("${CMAKE_MATCH_1} h is not 3.6e9 periods x ${CMAKE_MATCH_2} us"
        CMAKE_MATCH_1 STREQUAL CMAKE_MATCH_2)
  # 1.8e8 rows x row_bytes = 0.18 row_bytes GB (to 1 %, the header aside)
  math(EXPR low_centi "18 * ${row_bytes} * 99 / 100")
  math(EXPR high_centi "18 * ${row_bytes} * 101 / 100")
  foreach(bound low high)
    math(EXPR whole "${${bound}_centi} / 100")
    math(EXPR frac "${${bound}_centi} % 100 + 100")
    string(SUBSTRING "${frac}" 1 2 frac)
    set(${bound}_gb "${whole}.${frac}")
  endforeach()
  check("${gb} GB is not 1.8e8 rows x ${row_bytes} bytes (${low_gb}..${high_gb} GB)"
        gb GREATER_EQUAL low_gb AND gb LESS_EQUAL high_gb)
  expect_only_in_work_dir(scenario.json)
  # a run no longer than the pilot is not timed
  run_sim(rc err --set duration_s=0.2 --dry-run)
  check("--dry-run of a short run exited ${rc}: ${err}" rc EQUAL 0)
  check("a short run's estimate: ${last_stdout}" last_stdout MATCHES
        "4e\\+03 PWM periods at 20 kHz. wall time not measured \\(the run is no longer than the 10000-period pilot\\)\n$")
  # a real trace's bytes per row against the estimate's
  run_sim(rc err --set duration_s=0.5 --set output.trace_decimation=1 --quiet
          --csv "${WORK_DIR}/t.csv")
  check("pmsm-sim run exited ${rc}: ${err}" rc EQUAL 0)
  file(SIZE "${WORK_DIR}/t.csv" bytes)
  file(STRINGS "${WORK_DIR}/t.csv" rows)
  list(LENGTH rows n_lines)
  list(GET rows 0 header)
  string(LENGTH "${header}" header_bytes)
  math(EXPR measured "(${bytes} - ${header_bytes} - 1) / (${n_lines} - 1)")
  math(EXPR low "${measured} * 8 / 10")
  math(EXPR high "${measured} * 12 / 10")
  check("estimated ${row_bytes} bytes per row, a real trace has ${measured}"
        row_bytes GREATER_EQUAL low AND row_bytes LESS_EQUAL high)
  # a long run states its estimate on stderr before it starts (bench: no
  # outputs; stopped by the timeout long before its end)
  execute_process(COMMAND "${PMSM_SIM}" bench "${scn}" --set duration_s=36000
                  TIMEOUT 5 RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
  check("a long bench did not state its estimate first: ${err}" err MATCHES
        "^pmsm-sim: a long run: 36000 s simulated = [0-9.e+]+ PWM periods.*wall time about")
else()
  message(FATAL_ERROR "unknown CASE '${CASE}'")
endif()
