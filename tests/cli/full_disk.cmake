# A full disk while geovor writes an output: exit 4, a message naming the file and the reason, and
# nothing left in the output's directory (neither the target nor a temporary file).
#
#   cmake -DGEOVOR=<exe> -DMODE=tmpfs|fsize -DDIR=<empty dir> -DTARGET=<file name>
#         -DARGS=<geovor args separated by |, @OUT@ for the output path> [-DREASON=<regex>]
#         -P full_disk.cmake
# REASON: what the message must say after the file name (default: the errno text of ENOSPC or
#   EFBIG; GDAL's drivers word it their own way).
#
# MODE tmpfs: a 64 KiB tmpfs mounted on DIR in a private mount namespace (unshare -m; needs
#   CAP_SYS_ADMIN): write() fails with ENOSPC. Prints "SKIPPED: ..." when it cannot be mounted
#   (the test's SKIP_REGULAR_EXPRESSION).
# MODE fsize: RLIMIT_FSIZE of 64 KiB (`ulimit -f 128` in /bin/sh) with SIGXFSZ ignored: write()
#   past the limit fails with EFBIG ("File too large"). Works for any user.
cmake_minimum_required(VERSION 3.25)
foreach(v GEOVOR MODE DIR TARGET ARGS)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "full_disk.cmake: -D${v}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE ${DIR})
file(MAKE_DIRECTORY ${DIR})
set(out ${DIR}/${TARGET})
string(REPLACE "|" ";" args "${ARGS}")
string(REPLACE "@OUT@" "${out}" args "${args}")

# The shell runs geovor, then prints its exit code and what the directory holds (inside the
# namespace: the tmpfs is gone once it ends).
set(script [=[
d=$1; shift
if [ "$MODE" = tmpfs ]; then mount -t tmpfs -o size=64k geovor_full "$d" 2>/dev/null || { echo "SKIPPED: cannot mount a tmpfs"; exit 0; }; fi
if [ "$MODE" = fsize ]; then trap '' XFSZ; ulimit -f 128; fi
"$@"
echo "exit=$?"
echo "left:"; ls -A "$d"
]=])
if(MODE STREQUAL "tmpfs")
  find_program(UNSHARE unshare)
  if(NOT UNSHARE)
    message("SKIPPED: no unshare")
    return()
  endif()
  set(runner ${UNSHARE} -m)
elseif(MODE STREQUAL "fsize")
  set(runner)
else()
  message(FATAL_ERROR "full_disk.cmake: MODE is tmpfs or fsize, not ${MODE}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env MODE=${MODE} ${runner} /bin/sh -c "${script}" sh ${DIR} ${GEOVOR} ${args}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out_text ERROR_VARIABLE err)
if(out_text MATCHES "SKIPPED: [^\n]*")
  message("${CMAKE_MATCH_0}")
  return()
endif()
if(NOT rc EQUAL 0 AND NOT out_text MATCHES "exit=")
  message("SKIPPED: cannot run in a private mount namespace (${rc}): ${err}")
  return()
endif()
set(failures)
if(NOT out_text MATCHES "exit=4\n")
  list(APPEND failures "exit code is not 4")
endif()
string(REGEX REPLACE "([][+.*()^$?|\\\\])" "\\\\\\1" target_re "${TARGET}")
if(NOT DEFINED REASON)
  set(REASON "No space left on device|File too large")
endif()
if(NOT err MATCHES "${target_re}: [^\n]*(${REASON})")
  list(APPEND failures "stderr does not name ${TARGET} and the reason (${REASON})")
endif()
if(NOT out_text MATCHES "left:\n$")
  list(APPEND failures "files left behind")
endif()
if(failures)
  list(JOIN failures "\n  " text)
  message(FATAL_ERROR "${MODE}: geovor ${args}\n  ${text}\n--- stdout ---\n${out_text}--- stderr ---\n${err}")
endif()
message(STATUS "${MODE}: exit 4, nothing left in ${DIR}: ${err}")
