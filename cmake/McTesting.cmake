# mc_add_unit_test(<name> SOURCES <src>... LIBS <lib>... [LABELS <label>...]
#                  [TIMEOUT <seconds>])
# One cmocka executable per module, registered with ctest. LABELS defaults to
# "unit"; the labels used by the project are unit, sim, qemu and hil. Every
# test links mc_test_common (tests/common: mc_test.h, the cmocka include
# block, assert_near and the shared constants).
find_package(PkgConfig REQUIRED)
pkg_check_modules(CMOCKA REQUIRED IMPORTED_TARGET cmocka)

function(mc_add_unit_test name)
  cmake_parse_arguments(T "" "TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT T_SOURCES)
    message(FATAL_ERROR "mc_add_unit_test(${name}): SOURCES is required")
  endif()
  if(NOT T_LABELS)
    set(T_LABELS unit)
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} mc_test_common PkgConfig::CMOCKA mc_warnings m)
  add_test(NAME ${name} COMMAND ${name})
  set_tests_properties(${name} PROPERTIES LABELS "${T_LABELS}" TIMEOUT ${T_TIMEOUT})
endfunction()
