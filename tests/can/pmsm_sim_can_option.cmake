# pmsm-sim run --can and --realtime, run by ctest in CMake script mode:
#   cmake -DPMSM_SIM=<exe> -DSCENARIO=<json> -DWORK_DIR=<dir> -DCASE=<case> -P <this file>
# CASE can:      the CAN options' usage errors exit 2 with their message; then
#                `run --can vcan0`: where the kernel has no CAN (the build
#                machines) or no vcan0 it exits 2 with the clear message and
#                writes nothing; where vcan0 exists a 0.05 s run exits 0 and its
#                JSON says the commands came over CAN, with the link counts
# CASE realtime: `run --realtime` of 0.2 s simulated takes at least 0.2 s of wall
#                time and reports its pacing (batch, missed periods) in the
#                table and the JSON; without --realtime the JSON has "realtime": null
cmake_minimum_required(VERSION 3.25)

function(check message)
  if(NOT (${ARGN}))
    message(FATAL_ERROR "${message}")
  endif()
endfunction()

# pmsm-sim with the arguments must exit 2 with stderr matching the regex.
function(expect_usage_error regex)
  execute_process(COMMAND "${PMSM_SIM}" ${ARGN} RESULT_VARIABLE rc ERROR_VARIABLE err
                  OUTPUT_QUIET)
  check("pmsm-sim ${ARGN} should exit 2, exited ${rc}: ${err}" rc EQUAL 2)
  check("pmsm-sim ${ARGN}: unexpected stderr '${err}'" err MATCHES "${regex}")
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

if(CASE STREQUAL "can")
  expect_usage_error("--can-node needs --can IFNAME" run "${SCENARIO}" --can-node 1)
  expect_usage_error("--can-timeout needs --can IFNAME" run "${SCENARIO}" --can-timeout 0.2)
  expect_usage_error("--can-node '64' is not a node id 0\\.\\.63"
                     run "${SCENARIO}" --can vcan0 --can-node 64)
  expect_usage_error("--can-node '1x' is not a node id"
                     run "${SCENARIO}" --can vcan0 --can-node 1x)
  expect_usage_error("--can-timeout '0' is not a time in \\(0, 60\\] s"
                     run "${SCENARIO}" --can vcan0 --can-timeout 0)
  expect_usage_error("--can-timeout 'nan' is not a time"
                     run "${SCENARIO}" --can vcan0 --can-timeout nan)
  expect_usage_error("--can is an option of run, not of bench" bench "${SCENARIO}" --can vcan0)
  expect_usage_error("--realtime is an option of run, not of bench"
                     bench "${SCENARIO}" --realtime)
  expect_usage_error("option --can needs a value" run "${SCENARIO}" --can)
  expect_usage_error("CAN interface name 'a_name_far_too_long' must have 1 to 15 characters"
                     run "${SCENARIO}" --can a_name_far_too_long)

  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --can vcan0 --can-node 2 --set duration_s=0.05
            --json "${WORK_DIR}/metrics.json" --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
  if(rc EQUAL 0)
    # a kernel with CAN and vcan0 (the VM)
    file(READ "${WORK_DIR}/metrics.json" json)
    string(JSON source GET "${json}" command_source)
    check("command_source is '${source}', expected can" source STREQUAL "can")
    string(JSON ifname GET "${json}" can interface)
    check("can.interface is '${ifname}'" ifname STREQUAL "vcan0")
    string(JSON node GET "${json}" can node_id)
    check("can.node_id is '${node}'" node EQUAL 2)
    string(JSON drops GET "${json}" can link rx_overflow_drops)
    check("can.link.rx_overflow_drops is ${drops}" drops EQUAL 0)
    string(JSON n_metrics LENGTH "${json}" metrics)
    check("no metrics against the reference expected, found ${n_metrics}" n_metrics EQUAL 0)
    check("--can without --realtime should warn: '${err}'"
          err MATCHES "warning: --can without --realtime")
    message(STATUS "CAN present: pmsm-sim run --can vcan0 ran")
  else()
    check("pmsm-sim run --can vcan0 should exit 0 or 2, exited ${rc}: ${err}" rc EQUAL 2)
    set(no_can "CAN interface vcan0: socket\\(PF_CAN\\): Address family not supported by protocol \\(this kernel has no CAN. see the CAN section of host_sim/scenarios/README\\.md\\)")
    set(no_if "CAN interface vcan0: if_nametoindex: No such device \\(create a virtual one: ip link add dev vcan0 type vcan")
    check("unclear error for --can vcan0: '${err}'" err MATCHES "${no_can}|${no_if}")
    check("one error line expected: '${err}'" err MATCHES "^pmsm-sim: error: [^\n]*\n$")
    check("nothing may be written on that error" NOT EXISTS "${WORK_DIR}/metrics.json")
    message(STATUS "no CAN here: ${err}")
  endif()
elseif(CASE STREQUAL "realtime")
  string(TIMESTAMP t0 "%s%f")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --realtime --set duration_s=0.2
            --json "${WORK_DIR}/rt.json"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(TIMESTAMP t1 "%s%f")
  check("pmsm-sim run --realtime exited ${rc}: ${err}" rc EQUAL 0)
  math(EXPR wall_us "${t1} - ${t0}")
  check("a 0.2 s realtime run took ${wall_us} us of wall time" wall_us GREATER_EQUAL 200000)
  check("the table lacks the realtime line: ${out}"
        out MATCHES "realtime: paced to wall time in batches of 10 PWM periods. missed periods [0-9]+")
  file(READ "${WORK_DIR}/rt.json" json)
  string(JSON batch GET "${json}" realtime batch_periods)
  check("realtime.batch_periods is ${batch}, expected 10 (1 ms at 10 kHz)" batch EQUAL 10)
  string(JSON type TYPE "${json}" realtime missed_periods)
  check("realtime.missed_periods is ${type}" type STREQUAL "NUMBER")
  string(JSON late TYPE "${json}" realtime max_late_s)
  check("realtime.max_late_s is ${late}" late STREQUAL "NUMBER")
  string(JSON wall GET "${json}" wall_time_s)
  check("wall_time_s ${wall} should be at least the 0.2 s simulated" wall GREATER_EQUAL 0.199)
  string(JSON source GET "${json}" command_source)
  check("command_source is '${source}'" source STREQUAL "scenario")
  execute_process(
    COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set duration_s=0.05 --json "${WORK_DIR}/fast.json"
            --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  check("pmsm-sim run exited ${rc}: ${err}" rc EQUAL 0)
  file(READ "${WORK_DIR}/fast.json" json)
  string(JSON type TYPE "${json}" realtime)
  check("realtime should be null without --realtime, is ${type}" type STREQUAL "NULL")
  string(JSON type TYPE "${json}" can)
  check("can should be null without --can, is ${type}" type STREQUAL "NULL")
else()
  message(FATAL_ERROR "unknown CASE '${CASE}'")
endif()
