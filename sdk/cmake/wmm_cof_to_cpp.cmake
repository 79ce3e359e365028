# Build step (cmake -P): transcribes World Magnetic Model coefficient files in NOAA's WMM.COF text
# layout into C++ tables for libtern_sdk (sdk/src/world_magnetic_models.hpp declares them), so that
# tern::world_magnetic_field reads no file at run time.
#   cmake -DCOF_FILES="a.COF;b.COF" -DOUT=world_magnetic_models.cpp -P wmm_cof_to_cpp.cmake
# A COF file: a header "epoch model-name MM/DD/YYYY", rows "n m g h gdot hdot" for n = 1..N,
# m = 0..n in that order, then lines of 9s. Anything else stops the build with one line naming
# the file, the line and what was expected.
cmake_minimum_required(VERSION 3.25)
if(NOT COF_FILES OR NOT OUT)
  message(FATAL_ERROR "wmm_cof_to_cpp.cmake: needs -DCOF_FILES=<files> -DOUT=<file.cpp>")
endif()

set(_num "-?[0-9]+\\.[0-9]+")
set(_tables "")
set(_models "")
set(_k 0)
foreach(_file IN LISTS COF_FILES)
  get_filename_component(_base ${_file} NAME)
  file(STRINGS ${_file} _lines)
  set(_lineno 0)
  set(_n 1)
  set(_m 0)
  set(_nmax 0)
  set(_state header)
  set(_rows "")
  foreach(_line IN LISTS _lines)
    math(EXPR _lineno "${_lineno} + 1")
    if(_state STREQUAL "header")
      if(NOT _line MATCHES "^ *([0-9]+\\.[0-9]+) +([A-Za-z0-9._-]+) +([0-9][0-9]/[0-9][0-9]/[0-9][0-9][0-9][0-9]) *$")
        message(FATAL_ERROR "${_file}:${_lineno}: expected the header 'epoch model-name MM/DD/YYYY', got '${_line}'")
      endif()
      set(_epoch ${CMAKE_MATCH_1})
      set(_name ${CMAKE_MATCH_2})
      set(_date ${CMAKE_MATCH_3})
      set(_state rows)
    elseif(_state STREQUAL "rows" AND _line MATCHES "^9999+ *$")
      set(_state end)
    elseif(_state STREQUAL "rows")
      if(NOT _line MATCHES "^ *([0-9]+) +([0-9]+) +(${_num}) +(${_num}) +(${_num}) +(${_num}) *$")
        message(FATAL_ERROR "${_file}:${_lineno}: expected a row 'n m g h gdot hdot' (or the 9s that end the file), got '${_line}'")
      endif()
      if(NOT CMAKE_MATCH_1 EQUAL _n OR NOT CMAKE_MATCH_2 EQUAL _m)
        message(FATAL_ERROR "${_file}:${_lineno}: expected degree ${_n} order ${_m}, got n ${CMAKE_MATCH_1} m ${CMAKE_MATCH_2}")
      endif()
      string(APPEND _rows "    {${_n}, ${_m}, ${CMAKE_MATCH_3}, ${CMAKE_MATCH_4}, ${CMAKE_MATCH_5}, ${CMAKE_MATCH_6}},\n")
      set(_nmax ${_n})
      if(_m EQUAL _n)
        math(EXPR _n "${_n} + 1")
        set(_m 0)
      else()
        math(EXPR _m "${_m} + 1")
      endif()
    elseif(NOT _line MATCHES "^9999+ *$")
      message(FATAL_ERROR "${_file}:${_lineno}: nothing may follow the 9s that end the coefficients, got '${_line}'")
    endif()
  endforeach()
  if(NOT _state STREQUAL "end")
    message(FATAL_ERROR "${_file}:${_lineno}: ends without the line of 9s after the coefficients (truncated?)")
  endif()
  if(NOT _m EQUAL 0 OR _nmax LESS 1)
    message(FATAL_ERROR "${_file}:${_lineno}: degree ${_nmax} is incomplete (orders 0..${_nmax} needed)")
  endif()
  string(APPEND _tables "const CofRow kRows${_k}[] = {\n${_rows}};\n")
  string(APPEND _models "    {\"${_name}\", ${_epoch}, \"${_date}\", \"${_base}\", kRows${_k}, std::size(kRows${_k})},\n")
  math(EXPR _k "${_k} + 1")
endforeach()

list(JOIN COF_FILES " " _sources)
file(CONFIGURE OUTPUT ${OUT}.tmp @ONLY CONTENT "// Generated at build time by sdk/cmake/wmm_cof_to_cpp.cmake: do not edit. From: @_sources@
#include \"world_magnetic_models.hpp\"

#include <iterator>

namespace tern::wmm {
namespace {
@_tables@}  // namespace

const CofModel kModels[] = {
@_models@};
const std::size_t kModelCount = std::size(kModels);

}  // namespace tern::wmm
")
# Rewrite only on change: an unchanged table does not rebuild the library.
file(COPY_FILE ${OUT}.tmp ${OUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUT}.tmp)
