# Runs a command and checks its exit code and output; for CLI tests that must check the exit code
# (PASS_REGULAR_EXPRESSION alone ignores it).
#
#   cmake -DEXPECT_EXIT=<code> [-DSTDOUT_REGEX=<re>] [-DSTDERR_REGEX=<re>]
#         -P expect_exit.cmake -- <command> [<arg>...]
#
# Passes iff the command exits with <code> and, when given, its stdout matches STDOUT_REGEX and its
# stderr matches STDERR_REGEX (CMake regular expressions, unanchored).
cmake_minimum_required(VERSION 3.25)

if(NOT DEFINED EXPECT_EXIT)
  message(FATAL_ERROR "expect_exit.cmake: -DEXPECT_EXIT=<code> is required")
endif()

# The command is everything after "--" on the cmake command line.
set(cmd)
set(after_dashes FALSE)
math(EXPR last "${CMAKE_ARGC} - 1")
foreach(i RANGE 0 ${last})
  if(after_dashes)
    list(APPEND cmd "${CMAKE_ARGV${i}}")
  elseif(CMAKE_ARGV${i} STREQUAL "--")
    set(after_dashes TRUE)
  endif()
endforeach()
if(NOT cmd)
  message(FATAL_ERROR "expect_exit.cmake: no command given after --")
endif()

execute_process(COMMAND ${cmd}
  RESULT_VARIABLE rc
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err)

list(JOIN cmd " " cmd_text)
set(failures)
if(NOT rc STREQUAL "${EXPECT_EXIT}")
  list(APPEND failures "exit code is '${rc}', expected ${EXPECT_EXIT}")
endif()
if(DEFINED STDOUT_REGEX AND NOT out MATCHES "${STDOUT_REGEX}")
  list(APPEND failures "stdout does not match '${STDOUT_REGEX}'")
endif()
if(DEFINED STDERR_REGEX AND NOT err MATCHES "${STDERR_REGEX}")
  list(APPEND failures "stderr does not match '${STDERR_REGEX}'")
endif()

if(failures)
  list(JOIN failures "\n  " failure_text)
  message(FATAL_ERROR "command: ${cmd_text}\n  ${failure_text}\n"
                      "--- stdout ---\n${out}--- stderr ---\n${err}--------------")
endif()
message(STATUS "ok (exit ${rc}): ${cmd_text}")
