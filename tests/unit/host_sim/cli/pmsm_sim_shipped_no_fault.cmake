# No false trip on any shipped scenario (ctest label sim): every
# host_sim/scenarios/*.json runs through pmsm-sim and latches no fault.
#   cmake -DPMSM_SIM=<exe> -DSCENARIOS=<dir> -DWORK_DIR=<dir> -P <this file>
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
file(GLOB scenarios "${SCENARIOS}/*.json")
list(LENGTH scenarios n)
check("no scenarios found in ${SCENARIOS}" n GREATER 0)
foreach(path IN LISTS scenarios)
  get_filename_component(name "${path}" NAME_WE)
  execute_process(
    COMMAND "${PMSM_SIM}" run "${path}" --json "${WORK_DIR}/${name}.json" --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("pmsm-sim run ${name} exited ${rc}: ${err}" rc EQUAL 0)
  file(READ "${WORK_DIR}/${name}.json" json)
  string(JSON latched GET "${json}" faults latched)
  string(JSON n_faults LENGTH "${json}" faults latched)
  check("${name}: faults latched ${latched}" n_faults EQUAL 0)
  message(STATUS "${name}: no fault")
endforeach()
