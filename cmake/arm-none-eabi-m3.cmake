# Toolchain: Cortex-M3 (ARMv7-M, no FPU), soft-float ABI: float and double
# arithmetic are library calls (libgcc). Everything but the core flags is
# the Cortex-M4F toolchain's (compiler, binutils, linker flags, find modes),
# so that file is included and only the core flags are replaced here.
# Board port: hal/qemu_m3 (QEMU mps2-an385; CMakePresets.json preset m3).
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-m4f.cmake)

set(MC_M3_FLAGS "-mcpu=cortex-m3 -mthumb -mfloat-abi=soft -ffunction-sections -fdata-sections -g")
set(CMAKE_C_FLAGS_INIT "${MC_M3_FLAGS}")
set(CMAKE_ASM_FLAGS_INIT "${MC_M3_FLAGS}")
unset(MC_M4F_FLAGS)
