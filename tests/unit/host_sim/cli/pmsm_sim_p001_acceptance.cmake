# Paper 001 sensorless benchmark through pmsm-sim (ctest label sim), judged
# from the JSON metrics the simulator writes:
#   cmake -DPMSM_SIM=<exe> -DSCENARIOS=<dir> -DWORK_DIR=<dir> -P <this file>
# Runs the shipped paper001_benchmark_idapbc.json and paper001_benchmark_nam.json
# and checks the acceptance of the issue "Sensorless speed control of paper
# 001" (the project's reading of the paper's Figs. 2-4 and 11): IDA-PBC, nominal
# parameters: RMS speed error over tb = 5.5-7 s (120 rpm) <= 0.05 rpm, dip
# after each load step <= 20 rpm, RMS electrical angle error over 1.5-3 s and
# 5.5-7 s <= 1e-3 rad, RMS load-torque estimate error over 5.5-7 s <= 1e-3 N m,
# peak phase current <= 3 A, no fault; and the IDA-PBC dips smaller than the
# NAM baseline's at every load step (paper Section 5.2). The shipped
# robustness case paper001_idapbc_L150.json (plant inductance +50 %, the
# controller nominal) tracks like the nominal case: RMS speed error over
# 5.5-7 s <= 0.05 rpm, dips <= 20 rpm, no fault.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

# run(<scenario name> <out var>): the metrics JSON text of a full run.
function(run name out)
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIOS}/${name}.json" --json "${WORK_DIR}/${name}.json"
    RESULT_VARIABLE rc OUTPUT_VARIABLE table ERROR_VARIABLE err)
  message("${table}")
  check("pmsm-sim run ${name} exited ${rc}: ${err}" rc EQUAL 0)
  file(READ "${WORK_DIR}/${name}.json" json)
  string(JSON n_faults LENGTH "${json}" faults latched)
  check("${name}: faults latched: ${json}" n_faults EQUAL 0)
  set(${out} "${json}" PARENT_SCOPE)
endfunction()

# at_most(<json> <limit> <path>...): the metric at path is a number <= limit.
function(at_most json limit)
  string(JSON value ERROR_VARIABLE err GET "${json}" ${ARGN})
  string(REPLACE ";" "." where "${ARGN}")
  check("${where}: no value (${err})" NOT err AND NOT value STREQUAL "null")
  check("${where} = ${value}, acceptance <= ${limit}" value LESS_EQUAL limit)
  message(STATUS "${where} = ${value} (<= ${limit})")
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

run(paper001_benchmark_idapbc idapbc)
run(paper001_benchmark_nam nam)
run(paper001_idapbc_L150 idapbc_L150)

at_most("${idapbc}" 0.05 windows at_120rpm rms_error_rpm)
at_most("${idapbc}" 1e-3 windows at_50rpm rms_angle_error_e_rad)
at_most("${idapbc}" 1e-3 windows at_120rpm rms_angle_error_e_rad)
at_most("${idapbc}" 1e-3 windows at_120rpm rms_load_estimate_error_Nm)
# the peak over the whole run: every phase (the start's alignment included)
foreach(phase start hold profile)
  at_most("${idapbc}" 3.0 phases ${phase} peak_phase_current_A)
endforeach()

string(JSON n_steps LENGTH "${idapbc}" load_steps)
check("expected the 3 load steps of the benchmark, got ${n_steps}" n_steps EQUAL 3)
math(EXPR last "${n_steps} - 1")
foreach(i RANGE ${last})
  at_most("${idapbc}" 20.0 load_steps ${i} max_dip_rpm)
  string(JSON t GET "${idapbc}" load_steps ${i} t_s)
  string(JSON dip_paper GET "${idapbc}" load_steps ${i} max_dip_rpm)
  string(JSON dip_nam GET "${nam}" load_steps ${i} max_dip_rpm)
  check("load step at ${t} s: IDA-PBC dip ${dip_paper} rpm not below NAM's ${dip_nam} rpm"
        dip_paper LESS dip_nam)
  message(STATUS "load step at ${t} s: dip IDA-PBC ${dip_paper} rpm < NAM ${dip_nam} rpm")
endforeach()

at_most("${idapbc_L150}" 0.05 windows at_120rpm rms_error_rpm)
string(JSON n_steps LENGTH "${idapbc_L150}" load_steps)
check("L +50 %: expected the 3 load steps of the benchmark, got ${n_steps}" n_steps EQUAL 3)
foreach(i RANGE ${last})
  at_most("${idapbc_L150}" 20.0 load_steps ${i} max_dip_rpm)
endforeach()
