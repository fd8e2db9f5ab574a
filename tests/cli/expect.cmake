# Runs one command line and checks how it ends:
#   cmake -DEXPECT=fail|pass -DREGEX=<text that must appear> -DCOMMAND=<a|b|c> -P expect.cmake
# and optionally -DCODE=<the exact exit status>, -DSTDOUT=<regex stdout must
# match>, -DSTDERR=<regex stderr must match>, -DEMPTY=stdout|stderr (a stream
# that must stay empty): where each kind of message goes.
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
if(DEFINED CODE AND NOT code EQUAL CODE)
  message(FATAL_ERROR "expected exit ${CODE}, got ${code}")
endif()
if(STDOUT AND NOT out MATCHES "${STDOUT}")
  message(FATAL_ERROR "stdout does not match '${STDOUT}'")
endif()
if(STDERR AND NOT err MATCHES "${STDERR}")
  message(FATAL_ERROR "stderr does not match '${STDERR}'")
endif()
if(EMPTY STREQUAL "stdout" AND NOT out STREQUAL "")
  message(FATAL_ERROR "stdout should be empty")
endif()
if(EMPTY STREQUAL "stderr" AND NOT err STREQUAL "")
  message(FATAL_ERROR "stderr should be empty")
endif()
