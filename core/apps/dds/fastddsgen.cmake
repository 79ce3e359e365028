# core/apps/dds/fastddsgen.cmake: one fastddsgen -typeros2 run over the IDL files of one folder, run by
# core/apps/dds/CMakeLists.txt at build time as
#   cmake -DFASTDDSGEN=<fastddsgen> -DIDL_ROOTS=<idl/|...> -DOUT_DIR=<gen/pkg/msg> -DTEMP_DIR=<dir>
#         -DIDLS=<a.idl|b.idl|...> -P fastddsgen.cmake
#
# Why a wrapper (issue 45), as measured on Debian's fastddsgen 2.3.0:
#  - fastddsgen preprocesses every IDL it reads, the included ones too, into <temp dir>/<name>.cc
#    (default /tmp), so two runs reading the same included IDL (Time.idl) at once truncate each
#    other's file: "Time.idl:1:0: error: mismatched input '<EOF>'". Each run here gets its own
#    TEMP_DIR (-t): runs share nothing but the IDL files they only read.
#  - a parse error in an included IDL is printed but fastddsgen still exits 0. Here any line
#    with "error:", "ERROR" or "Exception in thread", a non-zero status or a missing output
#    fails the build, with fastddsgen's output.
foreach(_var FASTDDSGEN IDL_ROOTS OUT_DIR TEMP_DIR IDLS)
  if(NOT DEFINED ${_var} OR "${${_var}}" STREQUAL "")
    message(FATAL_ERROR "fastddsgen.cmake: -D${_var}=... is required")
  endif()
endforeach()
string(REPLACE "|" ";" _idls "${IDLS}")
string(REPLACE "|" ";" _roots "${IDL_ROOTS}")
set(_includes)
foreach(_root IN LISTS _roots)  # the include roots an #include "pkg/msg/X.idl" is looked up in
  list(APPEND _includes -I "${_root}")
endforeach()

file(REMOVE_RECURSE "${TEMP_DIR}")
file(MAKE_DIRECTORY "${TEMP_DIR}" "${OUT_DIR}")
execute_process(
  COMMAND "${FASTDDSGEN}" -typeros2 -replace -cs ${_includes} -t "${TEMP_DIR}" -d "${OUT_DIR}" ${_idls}
  RESULT_VARIABLE _status
  OUTPUT_VARIABLE _output
  ERROR_VARIABLE _output)
file(REMOVE_RECURSE "${TEMP_DIR}")

string(ASCII 27 _esc)
string(REGEX REPLACE "${_esc}\\[[0-9;]*m" "" _output "${_output}")  # fastddsgen colours its errors
set(_problem "")
if(NOT _status STREQUAL "0")
  set(_problem "exited with status ${_status}")
elseif(_output MATCHES "([^\n]*(error:|ERROR|Exception in thread)[^\n]*)")
  set(_problem "printed \"${CMAKE_MATCH_1}\" (and exited 0)")
else()
  foreach(_idl IN LISTS _idls)
    get_filename_component(_name "${_idl}" NAME_WE)
    foreach(_out "${_name}.h" "${_name}.cxx" "${_name}PubSubTypes.h" "${_name}PubSubTypes.cxx")
      if(NOT EXISTS "${OUT_DIR}/${_out}")
        set(_problem "wrote no ${OUT_DIR}/${_out}")
        break()
      endif()
    endforeach()
  endforeach()
endif()
if(_problem)
  message(FATAL_ERROR "fastddsgen ${_problem}: ${_idls}\n${_output}")
endif()
