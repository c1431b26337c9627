# write_if_changed(FILE TEXT): writes TEXT to FILE only when it differs, so an unchanged generated source
# does not make everything that depends on it rebuild. Shared by the build-time generators (-P scripts).
function(write_if_changed file text)
  set(old "")
  if(EXISTS "${file}")
    file(READ "${file}" old)
  endif()
  if(NOT old STREQUAL text)
    file(WRITE "${file}" "${text}")
  endif()
endfunction()
