# sensors.encoder.lines: the README, `pmsm-sim keys` and the validation state
# one range; run by ctest:
#   cmake -DPMSM_SIM=<exe> -DSCENARIO=<encoder FOC json> -DREADME=<scenarios README.md>
#         -DWORK_DIR=<dir> -P <this file>
# The README's range equals the one `pmsm-sim keys` prints (from the
# firmware's constants, 4 x lines <= MC_ENCODER_CPR_MAX = 2^23 counts);
# a run accepts its ends and rejects one line more; 0 (no encoder) is
# accepted with a sensorless estimator and rejected, at the key, with the
# encoder estimator.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

file(STRINGS "${README}" row REGEX "^\\| `sensors\\.encoder\\.lines` \\|")
if(NOT row MATCHES "^\\| `sensors\\.encoder\\.lines` \\| ([0-9]+)\\.\\.([0-9]+), or 0 ")
  message(FATAL_ERROR "README row of sensors.encoder.lines has no 'MIN..MAX, or 0' range: ${row}")
endif()
set(doc_min "${CMAKE_MATCH_1}")
set(doc_max "${CMAKE_MATCH_2}")
check("the README does not say what 0 is: ${row}" row MATCHES
      "0 is no encoder.*only with a sensorless `firmware\\.estimator`")

execute_process(COMMAND "${PMSM_SIM}" keys RESULT_VARIABLE rc OUTPUT_VARIABLE keys)
check("pmsm-sim keys exited ${rc}" rc EQUAL 0)
if(NOT keys MATCHES "\n  sensors\\.encoder\\.lines +integer +([0-9]+)\\.\\.([0-9]+), or 0 \\(no encoder")
  message(FATAL_ERROR "pmsm-sim keys lacks the range of sensors.encoder.lines:\n${keys}")
endif()
check("README says ${doc_min}..${doc_max}, pmsm-sim keys ${CMAKE_MATCH_1}..${CMAKE_MATCH_2}"
      doc_min EQUAL CMAKE_MATCH_1 AND doc_max EQUAL CMAKE_MATCH_2)
# the firmware counts 4 x lines, at most 2^23 (mc/encoder_tracker.h)
math(EXPR cpr_max "4 * ${doc_max}")
check("4 x ${doc_max} lines = ${cpr_max} counts, the firmware's maximum is 8388608"
      cpr_max EQUAL 8388608)

# run(<rc var> <err var> overrides...): a 20 ms run of the scenario.
function(run rc_var err_var)
  execute_process(COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set duration_s=0.02 --quiet ${ARGN}
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  set(${rc_var} "${rc}" PARENT_SCOPE)
  set(${err_var} "${err}" PARENT_SCOPE)
endfunction()

foreach(lines ${doc_min} ${doc_max})
  run(rc err --set sensors.encoder.lines=${lines})
  check("${lines} lines (documented) exited ${rc}: ${err}" rc EQUAL 0)
endforeach()
math(EXPR above "${doc_max} + 1")
run(rc err --set sensors.encoder.lines=${above})
check("${above} lines exited ${rc}, expected 3" rc EQUAL 3)
check("unexpected stderr: ${err}" err MATCHES
      "sensors\\.encoder\\.lines: out of range: expected whole number in \\[0, ${doc_max}\\]")
run(rc err --set sensors.encoder.lines=0)
check("0 lines with the encoder estimator exited ${rc}, expected 3" rc EQUAL 3)
check("unexpected stderr: ${err}" err MATCHES
      "sensors\\.encoder\\.lines: invalid value: expected ${doc_min}\\.\\.${doc_max} lines with firmware\\.estimator \"encoder\"")
run(rc err --set sensors.encoder.lines=0 --set firmware.estimator=flux_pll)
check("0 lines (no encoder) with a sensorless estimator exited ${rc}: ${err}" rc EQUAL 0)
