# check(<message> <if() condition words>...): FATAL_ERROR with the message
# unless the condition holds. Shared by the pmsm-sim scripts of this folder.
function(check message)
  if(NOT (${ARGN}))
    message(FATAL_ERROR "${message}")
  endif()
endfunction()
