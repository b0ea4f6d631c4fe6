# mc_size_report(<target> <library>...)
# Prints the text/data/bss size of each object of the given static libraries
# (Berkeley format, with totals) after every build.
function(mc_size_report name)
  set(archives "")
  foreach(lib IN LISTS ARGN)
    if(NOT TARGET ${lib})
      message(FATAL_ERROR "mc_size_report: no library target '${lib}'")
    endif()
    list(APPEND archives "$<TARGET_FILE:${lib}>")
  endforeach()
  add_custom_target(${name} ALL
    COMMAND ${CMAKE_SIZE} -t ${archives}
    DEPENDS ${ARGN}
    COMMENT "Firmware size report (arm-none-eabi-size, bytes)"
    VERBATIM)
endfunction()
