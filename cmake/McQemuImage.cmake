# Cortex-M4 images for QEMU mps2-an386 and their ctest registration
# (hal/qemu_m4/README.md). Cross builds only (arm-none-eabi-m4f.cmake).
#
# mc_add_qemu_image(<name> SOURCES <src>... [LIBS <lib>...]
#                   [DEFINITIONS <def>...])
#   An ELF image <name> linked with the mps2-an386 linker script, the
#   startup/semihosting/HAL binding (MC_QEMU_HAL_LIB, mc_hal_qemu_m4) and
#   -Wl,--wrap=mc_app_fast_isr (per-ISR instruction counts, isr_meter.h).
#   Prints its size after the build.
#
# mc_add_qemu_test(<name> IMAGE <image> [EXIT_STATUS <n>] [TIMEOUT <s>]
#                  [EXPECT "<key> <value> <abs_tol>"]...
#                  [MAX "<key> <limit>"]... [BUDGET <file>])
#   ctest (label qemu) that runs the image under
#   qemu-system-arm -M MC_QEMU_MACHINE (mps2-an386)
#   -icount shift=MC_QEMU_ICOUNT_SHIFT,align=off,sleep=off
#   through tests/qemu/run_qemu_test.py: the exit status must equal
#   EXIT_STATUS (default 0); each "CHECK <key> <value>" line the image
#   prints is compared: |value - expected| <= tol (EXPECT) or value <= limit
#   (MAX). A key named in EXPECT/MAX but not printed fails the test.
#   BUDGET: the RUN ISRs' instruction counts (max, mean) against the
#   image's entry in that file (tests/qemu/isr_budget.json): more than its
#   tolerance above fails.
#
# mc_add_qemu_estimate(<name> IMAGE <image> BUDGET <file> [TIMEOUT <s>])
#   ctest (labels qemu, qemu_estimate) that runs hal/qemu_m4/cycle_estimate.py
#   on the image: the window of ISRs the budget file's entry names is
#   traced in QEMU, every ISR's instruction count must equal the image's
#   SysTick meter, and the estimated cycles (max, mean per group) and the
#   ISR stack depth (-fstack-usage frames along the call graph) must stay
#   within the entry's values plus its tolerance. -LE qemu_estimate leaves
#   these out.

find_program(MC_QEMU_SYSTEM_ARM qemu-system-arm REQUIRED)
find_package(Python3 REQUIRED COMPONENTS Interpreter)

# The one definition of the icount shift: QEMU runs the images with it and
# the images (QEMU_M4_ICOUNT_SHIFT, hal/qemu_m4) convert ticks with it.
set(MC_QEMU_ICOUNT_SHIFT 6 CACHE STRING
  "QEMU -icount shift of the qemu images and tests (>= 6: exact counts)")
if(MC_QEMU_ICOUNT_SHIFT LESS 6 OR MC_QEMU_ICOUNT_SHIFT GREATER 10)
  message(FATAL_ERROR "MC_QEMU_ICOUNT_SHIFT must be in [6, 10] (hal/qemu_m4/qemu_m4.h)")
endif()
set(MC_QEMU_LINKER_SCRIPT ${PROJECT_SOURCE_DIR}/hal/qemu_m4/mps2_an386.ld)
# The board QEMU runs the images on, and the image support library they
# link (startup, semihosting, counter, ISR meter): a board port may set
# both before it adds its images (hal/qemu_m3: mps2-an385, mc_hal_qemu_m3).
set(MC_QEMU_MACHINE mps2-an386)
set(MC_QEMU_HAL_LIB mc_hal_qemu_m4)

# Frame sizes of the code that runs on the MCU (the firmware libraries and
# the HAL: every target with mc_firmware_opts): GCC writes <object>.su next
# to each object; hal/qemu_m4/cycle_estimate.py adds them up along the
# ISR's call graph (the ISR stack depth of tests/qemu/isr_budget.json).
# Only an extra output: the code is the same.
target_compile_options(mc_firmware_opts INTERFACE -fstack-usage)

function(mc_add_qemu_image name)
  cmake_parse_arguments(I "" "" "SOURCES;LIBS;DEFINITIONS" ${ARGN})
  if(NOT I_SOURCES)
    message(FATAL_ERROR "mc_add_qemu_image(${name}): SOURCES is required")
  endif()
  add_executable(${name} ${I_SOURCES})
  set_target_properties(${name} PROPERTIES SUFFIX ".elf")
  target_compile_definitions(${name} PRIVATE ${I_DEFINITIONS})
  # The vector table and the reset handler are referenced by nothing but
  # the linker script, the icount shift by nothing but tools reading the
  # ELF: -u pulls them out of the archive and keeps them through
  # --gc-sections.
  target_link_libraries(${name} PRIVATE ${I_LIBS} ${MC_QEMU_HAL_LIB} mc_warnings m)
  target_link_options(${name} PRIVATE
    -nostartfiles
    -Wl,-u,qemu_m4_vectors -Wl,-u,Reset_Handler -Wl,-u,qemu_m4_icount_shift
    -T${MC_QEMU_LINKER_SCRIPT}
    -Wl,--wrap=mc_app_fast_isr
    -Wl,-Map=$<TARGET_FILE_DIR:${name}>/${name}.map)
  set_property(TARGET ${name} APPEND PROPERTY LINK_DEPENDS ${MC_QEMU_LINKER_SCRIPT})
  add_custom_command(TARGET ${name} POST_BUILD
    COMMAND ${CMAKE_SIZE} $<TARGET_FILE:${name}>
    VERBATIM)
endfunction()

function(mc_add_qemu_test name)
  cmake_parse_arguments(T "" "IMAGE;EXIT_STATUS;TIMEOUT;BUDGET" "EXPECT;MAX" ${ARGN})
  if(NOT T_IMAGE)
    message(FATAL_ERROR "mc_add_qemu_test(${name}): IMAGE is required")
  endif()
  if(NOT DEFINED T_EXIT_STATUS)
    set(T_EXIT_STATUS 0)
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  set(checks "")
  foreach(e IN LISTS T_EXPECT)
    list(APPEND checks --expect ${e})
  endforeach()
  foreach(m IN LISTS T_MAX)
    list(APPEND checks --max ${m})
  endforeach()
  if(T_BUDGET)
    list(APPEND checks --budget ${T_BUDGET} --budget-image ${T_IMAGE})
  endif()
  add_test(NAME ${name}
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/qemu/run_qemu_test.py
      --qemu ${MC_QEMU_SYSTEM_ARM} --machine ${MC_QEMU_MACHINE}
      --icount-shift ${MC_QEMU_ICOUNT_SHIFT} --exit-status ${T_EXIT_STATUS} --timeout ${T_TIMEOUT}
      ${checks} $<TARGET_FILE:${T_IMAGE}>)
  set_tests_properties(${name} PROPERTIES LABELS qemu
    TIMEOUT ${T_TIMEOUT})
endfunction()

function(mc_add_qemu_estimate name)
  cmake_parse_arguments(E "" "IMAGE;BUDGET;TIMEOUT" "" ${ARGN})
  if(NOT E_IMAGE OR NOT E_BUDGET)
    message(FATAL_ERROR "mc_add_qemu_estimate(${name}): IMAGE and BUDGET are required")
  endif()
  if(NOT E_TIMEOUT)
    set(E_TIMEOUT 120)
  endif()
  add_test(NAME ${name}
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/hal/qemu_m4/cycle_estimate.py
      --qemu ${MC_QEMU_SYSTEM_ARM}
      --su-root ${CMAKE_BINARY_DIR}/firmware --su-root ${CMAKE_BINARY_DIR}/hal
      --budget ${E_BUDGET} --image ${E_IMAGE}
      $<TARGET_FILE:${E_IMAGE}>)
  set_tests_properties(${name} PROPERTIES LABELS "qemu;qemu_estimate"
    TIMEOUT ${E_TIMEOUT})
endfunction()
