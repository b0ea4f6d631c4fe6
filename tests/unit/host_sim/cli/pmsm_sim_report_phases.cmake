# Reports that do not mislead (pmsm-sim run, JSON and table), run by ctest:
#   cmake -DPMSM_SIM=<exe> -DSCENARIO=<sensorless json with time_offset_s> -DWORK_DIR=<dir>
#         -P <this file>
# The scenario has a time offset T0 (profile time = simulated time - T0); an
# external fault is injected at simulated time T0 + 0.5 s (injections are in
# simulated time):
# - the first fault's time is given in both time bases, each named as such
#   (faults.first_fault_sim_time_s, faults.first_fault_profile_time_s), and
#   the table says which is which (it prints "profile time" in its header);
# - the peaks are reported per phase of the run (phases.start, hold,
#   profile, fault), each phase's times in simulated time; the sensorless
#   alignment's currents (the start) are not those of the profile, and the
#   coasting after the fault is its own phase; no whole-run peak is left.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

file(READ "${SCENARIO}" scenario_text)
string(JSON t0 GET "${scenario_text}" time_offset_s)
string(REGEX REPLACE "\\.0*$" "" t0_s "${t0}")
check("the scenario needs a whole-second time offset, has ${t0}"
      t0_s MATCHES "^[1-9][0-9]*$")
set(t_fault "${t0_s}.5")
set(t_end "${t0_s}.6")

execute_process(
  COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set "duration_s=${t_end}"
          --set "fault_injections=[{\"kind\": \"fault_input\", \"t_start_s\": ${t_fault}}]"
          --json "${WORK_DIR}/metrics.json"
  RESULT_VARIABLE rc OUTPUT_VARIABLE table ERROR_VARIABLE err)
check("pmsm-sim run exited ${rc}: ${err}" rc EQUAL 0)
file(READ "${WORK_DIR}/metrics.json" json)

# --- the first fault in both time bases, named
string(JSON sim_t GET "${json}" faults first_fault_sim_time_s)
string(JSON profile_t GET "${json}" faults first_fault_profile_time_s)
string(JSON offset GET "${json}" time_offset_s)
check("first_fault_sim_time_s ${sim_t}, injected at ${t_fault} s simulated"
      sim_t GREATER_EQUAL ${t_fault} AND sim_t LESS ${t_fault}001)
check("time_offset_s ${offset} is the scenario's ${t0}" offset EQUAL t0)
# profile = simulated - T0 = 0.5 s (the injection's 0.5 s after T0)
check("first_fault_profile_time_s ${profile_t}, expected 0.5 (simulated ${sim_t} - ${t0})"
      profile_t GREATER_EQUAL 0.5 AND profile_t LESS 0.5001)
string(JSON ambiguous ERROR_VARIABLE missing GET "${json}" faults first_fault_t_s)
check("the JSON still has the unlabelled first_fault_t_s" missing)
check("the table lacks its profile-time header:\n${table}" table MATCHES
      "times below in profile time = simulated time - ${t0_s} s")
check("the table does not label the fault time:\n${table}" table MATCHES
      "first at simulated t = ${t0_s}\\.500000 s = profile time 0\\.500000 s")

# --- peaks by phase
foreach(key peak_phase_current_A peak_phase_voltage_V)
  string(JSON whole ERROR_VARIABLE missing GET "${json}" metrics ${key})
  check("a whole-run metrics.${key} (${whole}) mixes the phases" missing)
endforeach()
foreach(phase start hold profile fault)
  string(JSON type TYPE "${json}" phases ${phase})
  check("phases.${phase} is ${type}, expected an object" type STREQUAL OBJECT)
  string(JSON from_${phase} GET "${json}" phases ${phase} from_sim_time_s)
  string(JSON to_${phase} GET "${json}" phases ${phase} to_sim_time_s)
  string(JSON i_${phase} GET "${json}" phases ${phase} peak_phase_current_A)
  string(JSON v_${phase} GET "${json}" phases ${phase} peak_phase_voltage_V)
endforeach()
# contiguous, in order: 0 -> alignment -> hold -> T0 -> fault -> end
check("start from ${from_start}" from_start EQUAL 0)
check("hold ${from_hold}..${to_hold} s after the start ..${to_start} s and before T0 ${t0}"
      from_hold GREATER to_start AND to_hold LESS t0)
check("profile from ${from_profile} s, expected T0 = ${t0} s" from_profile EQUAL t0)
check("profile ends at ${to_profile} s, the fault at ${sim_t} s" to_profile EQUAL sim_t)
check("fault phase ${from_fault}..${to_fault} s after the fault at ${sim_t} s"
      from_fault GREATER sim_t AND from_fault LESS ${t_fault}001)
# The alignment (firmware.align defaults: a 2 A vector, its damping current
# within 2 A, |i| <= 2 sqrt(2) A) drives the start's currents; the profile's
# first 0.5 s is an unloaded ramp to 25 rpm (J 0.012 kg m^2, a few tens of
# mA), so its peak is far below; with the PWM off after the fault the
# currents are zero (outputs off, back-EMF below the bus: the diodes block).
check("start peak ${i_start} A, expected the 2 A alignment (<= 2.83 A)"
      i_start GREATER_EQUAL 2.0 AND i_start LESS_EQUAL 2.83)
check("profile peak ${i_profile} A should be well below the alignment's ${i_start} A"
      i_profile LESS 0.5)
check("after the fault ${i_fault} A should be 0 (PWM off)" i_fault EQUAL 0)
check("the table lacks the phase rows:\n${table}" table MATCHES
      "start \\(calibration, alignment\\) \\[0, [0-9.]+\\] s:.*hold before the profile.*under the profile \\[${t0_s}, .*after the fault \\[")

# --- without a fault the fault phase is null, and without a time offset
#     there is no hold
execute_process(
  COMMAND "${PMSM_SIM}" run "${SCENARIO}" --set duration_s=2.2 --set time_offset_s=0
          --json "${WORK_DIR}/no_fault.json" --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE err)
check("pmsm-sim run without a fault exited ${rc}: ${err}" rc EQUAL 0)
file(READ "${WORK_DIR}/no_fault.json" json)
foreach(phase hold fault)
  string(JSON type TYPE "${json}" phases ${phase})
  check("phases.${phase} is ${type}, expected NULL" type STREQUAL NULL)
endforeach()
string(JSON type TYPE "${json}" faults first_fault_sim_time_s)
check("first_fault_sim_time_s without a fault is ${type}" type STREQUAL NULL)
