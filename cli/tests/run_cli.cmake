# Runs the steady tool once and checks what it did (cmake -P script, used by cli/CMakeLists.txt).
#
# -D variables:
#   STEADY        the binary
#   ARGS          its arguments, separated by '|' (an argument may contain blanks, not '|')
#   WORKDIR       working directory (default: the current one)
#   EXIT          expected exit status (default 0)
#   STDERR_REGEX  regular expression that standard error must match
#   STDOUT_REGEX  regular expression that standard output must match
#   CHECKER       the steady_cli_json_check binary; with JSON:
#   JSON          '|'-separated expectations on standard output (see tests/json_check.cpp), or
#   JSON_FILE     on this file instead, which the run writes (it is removed before the run)
#   TOL           numeric tolerance for JSON (default 1e-12)
#   SAME_AS       '|'-separated arguments of a second run whose standard output must be identical
#   OUT           file that receives standard output (for the JSON check)
#   STDIN         file fed to standard input (default: none)
#   FILE          a file the run writes: removed before the run; then, with
#   FILE_REGEX    regular expression its first 64 KiB must match, and/or
#   FILE_SIZE     its size in bytes
#   ABSENT        '|'-separated glob patterns that must match nothing after the run (matching
#                 files are removed before it): files a failing run must not leave behind
#
# A failing run (EXIT != 0) must leave standard output empty and report
# "steady: error [<reason>]: ..." on standard error.

if(NOT DEFINED WORKDIR OR WORKDIR STREQUAL "")
  set(WORKDIR ".")
endif()
if(NOT DEFINED EXIT OR EXIT STREQUAL "")
  set(EXIT 0)
endif()
if(NOT DEFINED TOL OR TOL STREQUAL "")
  set(TOL 1e-12)
endif()

string(REPLACE "|" ";" args "${ARGS}")
string(REPLACE "|" ";" absent "${ABSENT}")
if(DEFINED FILE AND NOT FILE STREQUAL "")
  file(REMOVE "${FILE}")
endif()
if(DEFINED JSON_FILE AND NOT JSON_FILE STREQUAL "")
  file(REMOVE "${JSON_FILE}")
endif()
foreach(pattern IN LISTS absent)
  file(GLOB stale "${pattern}")
  if(stale)
    file(REMOVE ${stale})
  endif()
endforeach()
set(input "")
if(DEFINED STDIN AND NOT STDIN STREQUAL "")
  set(input INPUT_FILE "${STDIN}")
endif()
execute_process(COMMAND "${STEADY}" ${args}
  WORKING_DIRECTORY "${WORKDIR}"
  ${input}
  RESULT_VARIABLE status
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err)

set(failures "")
function(fail what)
  set(failures "${failures}  - ${what}\n" PARENT_SCOPE)
endfunction()

if(NOT status STREQUAL "${EXIT}")
  fail("exit status ${status}, expected ${EXIT}")
endif()
if(NOT EXIT EQUAL 0)
  if(NOT out STREQUAL "")
    fail("standard output is not empty after a failure")
  endif()
  if(NOT err MATCHES "^steady: error \\[[a-z0-9-]+\\]: ")
    fail("standard error does not start with 'steady: error [<reason>]: '")
  endif()
endif()
if(DEFINED STDERR_REGEX AND NOT STDERR_REGEX STREQUAL "" AND NOT err MATCHES "${STDERR_REGEX}")
  fail("standard error does not match '${STDERR_REGEX}'")
endif()
if(DEFINED STDOUT_REGEX AND NOT STDOUT_REGEX STREQUAL "" AND NOT out MATCHES "${STDOUT_REGEX}")
  fail("standard output does not match '${STDOUT_REGEX}'")
endif()

if(DEFINED JSON AND NOT JSON STREQUAL "")
  if(DEFINED JSON_FILE AND NOT JSON_FILE STREQUAL "")
    set(json_input "${JSON_FILE}")
  else()
    file(WRITE "${OUT}" "${out}")
    set(json_input "${OUT}")
  endif()
  string(REPLACE "|" ";" specs "${JSON}")
  execute_process(COMMAND "${CHECKER}" "${json_input}" "${TOL}" ${specs}
    RESULT_VARIABLE check_status
    ERROR_VARIABLE check_err)
  if(NOT check_status EQUAL 0)
    fail("JSON output does not match:\n${check_err}")
  endif()
endif()

if(DEFINED FILE AND NOT FILE STREQUAL "")
  if(NOT EXISTS "${FILE}")
    fail("the output file ${FILE} does not exist")
  else()
    if(DEFINED FILE_REGEX AND NOT FILE_REGEX STREQUAL "")
      file(READ "${FILE}" head LIMIT 65536)
      if(NOT head MATCHES "${FILE_REGEX}")
        fail("the output file ${FILE} does not match '${FILE_REGEX}'")
      endif()
    endif()
    if(DEFINED FILE_SIZE AND NOT FILE_SIZE STREQUAL "")
      file(SIZE "${FILE}" size)
      if(NOT size EQUAL FILE_SIZE)
        fail("the output file ${FILE} has ${size} bytes, expected ${FILE_SIZE}")
      endif()
    endif()
  endif()
endif()
foreach(pattern IN LISTS absent)
  file(GLOB left LIST_DIRECTORIES true "${pattern}")
  if(left)
    fail("left behind: ${left}")
  endif()
endforeach()

if(DEFINED SAME_AS AND NOT SAME_AS STREQUAL "")
  string(REPLACE "|" ";" args2 "${SAME_AS}")
  execute_process(COMMAND "${STEADY}" ${args2}
    WORKING_DIRECTORY "${WORKDIR}"
    RESULT_VARIABLE status2
    OUTPUT_VARIABLE out2
    ERROR_VARIABLE err2)
  if(NOT status2 EQUAL 0)
    fail("the comparison run failed with status ${status2}: ${err2}")
  elseif(NOT out STREQUAL out2)
    fail("standard output differs from that of: steady ${args2}")
  endif()
endif()

if(NOT failures STREQUAL "")
  string(REPLACE ";" " " shown "${args}")
  message(FATAL_ERROR "steady ${shown}\n(in ${WORKDIR})\n${failures}"
                      "--- exit status: ${status}\n--- stdout:\n${out}\n--- stderr:\n${err}")
endif()
