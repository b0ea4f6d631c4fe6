# A parameter sweep end to end through tools/sweep.sh and GNU parallel
# (ctest label sim):
#   cmake -DPMSM_SIM=<exe> -DBUILD_DIR=<build> -DREPO=<source dir>
#         -DSCENARIOS=<dir> -DWORK_DIR=<dir> -P <this file>
# A 2 x 2 sweep of the FOC benchmark shortened to 0.3 s over the plant's
# R x {1.0, 1.5} and psi x {1.0, 200}: psi = 200 is outside the format's
# (0, 100], so those two points' runs fail with exit status 3. Checks the
# collected table (results.csv): every point present once with its axis
# values; each valid point's metrics equal to those of a direct
# `pmsm-sim run --json` of the same point (the expectation, computed here);
# each invalid point reported as failed with exit code 3 and the
# simulator's error, not dropped; the heat maps written. Needs GNU parallel
# (Debian package parallel, installed by tools/setup.sh) and the project's
# venv.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

find_program(PARALLEL parallel)
check("GNU parallel not found: install Debian package parallel (tools/setup.sh does)"
      PARALLEL)
check("pmsm-sim ${PMSM_SIM} is not the one tools/sweep.sh finds in BUILD_DIR ${BUILD_DIR}"
      PMSM_SIM STREQUAL "${BUILD_DIR}/host_sim/cli/pmsm-sim")

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(scenario "${SCENARIOS}/paper001_benchmark_foc.json")
set(sweep "${WORK_DIR}/tiny_sweep.json")
file(WRITE "${sweep}" "{
  \"sweep_format_version\": 1,
  \"name\": \"tiny\",
  \"bases\": [{\"name\": \"foc\", \"scenario\": \"${scenario}\"}],
  \"set\": [\"duration_s=0.3\"],
  \"axes\": [
    {\"name\": \"R\", \"keys\": \"disturbances.mismatch.R\", \"values\": [1.0, 1.5]},
    {\"name\": \"psi\", \"keys\": [\"disturbances.mismatch.psi\"], \"values\": [1.0, 200]}
  ],
  \"metrics\": [
    {\"name\": \"rms\", \"path\": \"metrics.rms_tracking_error_rpm\"},
    {\"name\": \"peak_i\", \"path\": \"phases.profile.peak_phase_current_A\"},
    {\"name\": \"faults\", \"path\": \"faults.latched\"}
  ],
  \"stable\": {\"no_fault\": true, \"max\": {\"rms\": 100}}
}
")

set(out "${WORK_DIR}/out")
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env PARALLEL_JOBS=2
          "${REPO}/tools/sweep.sh" "${sweep}" "${out}" "${BUILD_DIR}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
message("${stdout}")
check("tools/sweep.sh exited ${rc}: ${stderr}" rc EQUAL 0)

file(STRINGS "${out}/jobs.txt" jobs)
list(LENGTH jobs n_jobs)
check("jobs.txt: expected 4 jobs (2 x 2), found ${n_jobs}" n_jobs EQUAL 4)
file(STRINGS "${out}/joblog.tsv" joblog)
list(LENGTH joblog n_log)
check("joblog.tsv: expected a header and 4 jobs run by GNU parallel, found ${n_log} lines"
      n_log EQUAL 5)
check("no heat map ${out}/heatmap.png" EXISTS "${out}/heatmap.png")

# results.csv: point,base,R,psi,exit_code,status,rms,peak_i,faults,reason
file(READ "${out}/results.csv" text)
# One list element a line: brackets (in the simulator's messages) and ';'
# would split or join CMake list elements.
string(REPLACE "[" "<" text "${text}")
string(REPLACE "]" ">" text "${text}")
string(REPLACE ";" "," text "${text}")
string(STRIP "${text}" text)
string(REPLACE "\n" ";" lines "${text}")
list(LENGTH lines n_lines)
check("results.csv: expected a header and 4 points, found ${n_lines} lines" n_lines EQUAL 5)
list(GET lines 0 header)
check("results.csv header: ${header}"
      header STREQUAL "point,base,R,psi,exit_code,status,rms,peak_i,faults,reason")
list(REMOVE_AT lines 0)

# The points in expansion order: the last axis varies fastest.
set(expected_R 1.0 1.0 1.5 1.5)
set(expected_psi 1.0 200 1.0 200)
set(i 0)
foreach(line IN LISTS lines)
  math(EXPR point "${i} + 1")
  list(GET expected_R ${i} R)
  list(GET expected_psi ${i} psi)
  # (CMake keeps 9 groups: the reason, last, is matched on the whole line.)
  string(REGEX MATCH "^([^,]*),([^,]*),([^,]*),([^,]*),([^,]*),([^,]*),([^,]*),([^,]*),([^,]*),"
         m "${line}")
  check("results.csv: malformed row: ${line}" m)
  set(what "point ${point} (R ${R}, psi ${psi}): ${line}")
  check("${what}: wrong index or base" CMAKE_MATCH_1 EQUAL point AND CMAKE_MATCH_2 STREQUAL "foc")
  check("${what}: wrong axis values" CMAKE_MATCH_3 EQUAL R AND CMAKE_MATCH_4 EQUAL psi)
  if(psi EQUAL 200)
    check("${what}: expected failed with exit code 3"
          CMAKE_MATCH_5 STREQUAL "3" AND CMAKE_MATCH_6 STREQUAL "failed")
    string(LENGTH "${CMAKE_MATCH_7}${CMAKE_MATCH_8}${CMAKE_MATCH_9}" n_metric_chars)
    check("${what}: expected no metrics" n_metric_chars EQUAL 0)
    check("${what}: expected the simulator's error as the reason"
          line MATCHES ",[^,]*pmsm-sim: error: [^,]*disturbances\\.mismatch\\.psi: out of range")
  else()
    set(row_rms "${CMAKE_MATCH_7}")
    set(row_peak "${CMAKE_MATCH_8}")
    check("${what}: expected exit code 0, stable, no faults"
          CMAKE_MATCH_5 STREQUAL "0" AND CMAKE_MATCH_6 STREQUAL "stable"
          AND CMAKE_MATCH_9 STREQUAL "none")
    # The expectation: the same point run directly.
    set(direct "${WORK_DIR}/direct_${point}.json")
    execute_process(
      COMMAND "${PMSM_SIM}" run "${scenario}" --set duration_s=0.3
              --set disturbances.mismatch.R=${R} --set disturbances.mismatch.psi=${psi}
              --quiet --json "${direct}"
      RESULT_VARIABLE rc ERROR_VARIABLE err)
    check("direct run of point ${point} exited ${rc}: ${err}" rc EQUAL 0)
    file(READ "${direct}" json)
    string(JSON rms GET "${json}" metrics rms_tracking_error_rpm)
    string(JSON peak GET "${json}" phases profile peak_phase_current_A)
    check("${what}: rms ${row_rms} differs from the direct run's ${rms}" row_rms EQUAL rms)
    check("${what}: peak_i ${row_peak} differs from the direct run's ${peak}" row_peak EQUAL peak)
    message(STATUS "point ${point}: rms ${row_rms} rpm, peak ${row_peak} A = direct run")
  endif()
  math(EXPR i "${i} + 1")
endforeach()
