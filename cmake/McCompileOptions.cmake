# Compile options shared by every target of the project.
#
# mc_warnings     : warnings as errors, for all code (firmware, plant, tests).
# mc_firmware_opts: extra rules for code that runs on the MCU: float only
#                   (no silent promotion to double), no errno from libm.
#                   -ffast-math is NOT used: it implies -ffinite-math-only,
#                   which would let the compiler delete the isfinite() checks
#                   that turn NaN/Inf into faults.
add_library(mc_warnings INTERFACE)
target_compile_options(mc_warnings INTERFACE
  -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes
  -Wpointer-arith -Wundef -Wvla)

add_library(mc_firmware_opts INTERFACE)
target_link_libraries(mc_firmware_opts INTERFACE mc_warnings)
target_compile_options(mc_firmware_opts INTERFACE
  -Wdouble-promotion -Wfloat-conversion -fno-math-errno)
