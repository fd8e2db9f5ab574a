# Runs one command line and checks how it ends:
#   cmake -DEXPECT=fail|pass -DREGEX=<text that must appear> -DCOMMAND=<a|b|c> -P expect.cmake
# A failure must be a clean non-zero exit with the expected message: a
# crash (signal, "Segmentation fault", MPI abort) fails the check too.
string(REPLACE "|" ";" COMMAND "${COMMAND}")  # the list travels |-separated
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 300)
set(all "${out}${err}")
message("exit: ${code}\n${all}")
if(NOT code MATCHES "^[0-9]+$")
  message(FATAL_ERROR "the command did not exit normally: ${code}")
endif()
if(EXPECT STREQUAL "fail" AND code EQUAL 0)
  message(FATAL_ERROR "expected a non-zero exit")
endif()
if(EXPECT STREQUAL "pass" AND NOT code EQUAL 0)
  message(FATAL_ERROR "expected exit 0, got ${code}")
endif()
foreach(bad "Segmentation fault" "core dumped" "signal" "terminate called" "MPI_ABORT")
  string(FIND "${all}" "${bad}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "the output shows a crash ('${bad}')")
  endif()
endforeach()
if(REGEX AND NOT all MATCHES "${REGEX}")
  message(FATAL_ERROR "the output does not match '${REGEX}'")
endif()
