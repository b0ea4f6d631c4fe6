# Names and values pmsm-sim echoes in its errors are escaped (control
# characters as \n, \t, \xNN), never sent raw to the terminal; run by ctest:
#   cmake -DPMSM_SIM=<exe> -DWORK_DIR=<dir> -P <this file>
# A scenario file whose name holds a tab and an escape character, with an
# escape sequence and a newline in a key and a bell in a string value; a
# --set key with a newline; an unknown command with an escape character.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
string(ASCII 27 esc)
string(ASCII 7 bell)

# Every control character (1-31, 127), for a regex class.
string(ASCII 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30
       31 127 controls)

# expect_clean(<what> <stderr>): one line, no raw control character.
function(expect_clean what text)
  string(REGEX REPLACE "\n$" "" line "${text}")
  string(REGEX MATCH "[${controls}]" raw "${line}")
  check("${what}: a raw control character on stderr: '${line}'" "x${raw}" STREQUAL "x")
endfunction()

set(motor "\"motor\": {\"R_ohm\": 0.2, \"Ld_H\": 0.004, \"psi_Wb\": 0.17, \"pole_pairs\": 3, \"J_kgm2\": 0.01")
set(name "${WORK_DIR}/s\tc${esc}.json")
file(WRITE "${name}"
  "{\"format_version\": 2, \"duration_s\": 1, ${motor}, \"R\\u001b[2J\\nx\": 1},"
  " \"reference\": {\"mode\": \"speed\", \"speed_rad_s\": 0}}")
execute_process(COMMAND "${PMSM_SIM}" run "${name}" RESULT_VARIABLE rc ERROR_VARIABLE err)
check("a bad key should exit 3, exited ${rc}" rc EQUAL 3)
expect_clean("key and file name" "${err}")
check("unexpected stderr: ${err}" err MATCHES
      "s\\\\tc\\\\x1b\\.json: motor\\.R\\\\x1b\\[2J\\\\nx: unknown key")

file(WRITE "${WORK_DIR}/value.json"
  "{\"format_version\": 2, \"duration_s\": 1, ${motor}},"
  " \"reference\": {\"mode\": \"sp\\u0007eed\\r\\n\"}}")
execute_process(COMMAND "${PMSM_SIM}" run "${WORK_DIR}/value.json"
                RESULT_VARIABLE rc ERROR_VARIABLE err)
check("a bad value should exit 3, exited ${rc}" rc EQUAL 3)
expect_clean("string value" "${err}")
check("unexpected stderr: ${err}" err MATCHES "found string \"sp\\\\x07eed\\\\r\\\\n\"")

file(WRITE "${WORK_DIR}/ok.json"
  "{\"format_version\": 2, \"duration_s\": 1, ${motor}},"
  " \"reference\": {\"mode\": \"speed\", \"speed_rad_s\": 0}}")
execute_process(COMMAND "${PMSM_SIM}" run "${WORK_DIR}/ok.json" --set "a\nb${bell}=1"
                RESULT_VARIABLE rc ERROR_VARIABLE err)
check("an unknown --set key should exit 3, exited ${rc}" rc EQUAL 3)
expect_clean("--set key" "${err}")
check("unexpected stderr: ${err}" err MATCHES "ok\\.json: a\\\\nb\\\\x07: unknown key")

execute_process(COMMAND "${PMSM_SIM}" "r${esc}[31mun" RESULT_VARIABLE rc ERROR_VARIABLE err)
check("an unknown command should exit 2, exited ${rc}" rc EQUAL 2)
expect_clean("command" "${err}")
check("unexpected stderr: ${err}" err MATCHES "unknown command 'r\\\\x1b\\[31mun'")
