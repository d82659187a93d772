# Compile every generated header translation unit on its own, as C11 and,
# when a C++ compiler is known, as C++11. Run by ctest (abi_headers):
#
#   cmake -DCC=... [-DCXX=...] -DC_WARNINGS=a|b -DTUS=x.c|y.c -DINCLUDES=d1|d2 -P check_headers.cmake
#
# Lists are passed with '|' separators. Every failure is reported before the
# script fails.
cmake_minimum_required(VERSION 3.16)

foreach(var CC TUS INCLUDES)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "check_headers.cmake: ${var} is not set")
  endif()
endforeach()

string(REPLACE "|" ";" tus "${TUS}")
string(REPLACE "|" ";" c_warnings "${C_WARNINGS}")
string(REPLACE "|" ";" include_dirs "${INCLUDES}")
set(includes)
foreach(dir ${include_dirs})
  list(APPEND includes "-I${dir}")
endforeach()

set(cxx_warnings -Wall -Wextra -Wpedantic -Wshadow -Werror)
set(failed)
set(checked 0)

function(check_one lang compiler tu)
  if(lang STREQUAL "C")
    set(flags -std=c11 ${c_warnings})
  else()
    set(flags -x c++ -std=c++11 ${cxx_warnings})
  endif()
  execute_process(
    COMMAND ${compiler} ${flags} ${includes} -fsyntax-only ${tu}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  get_filename_component(name ${tu} NAME_WE)
  if(rc EQUAL 0)
    message("ok      ${lang}\tbrdffit/${name}.h")
  else()
    message("FAILED  ${lang}\tbrdffit/${name}.h\n${out}")
    set(failed ${failed} "${lang}:brdffit/${name}.h" PARENT_SCOPE)
  endif()
endfunction()

foreach(tu ${tus})
  check_one(C "${CC}" ${tu})
  math(EXPR checked "${checked} + 1")
  if(CXX)
    check_one(C++ "${CXX}" ${tu})
    math(EXPR checked "${checked} + 1")
  endif()
endforeach()

if(NOT CXX)
  message("note: no C++ compiler was found; the headers were checked as C only")
endif()
if(failed)
  message(FATAL_ERROR "public headers that do not compile alone: ${failed}")
endif()
message("abi_headers: ${checked} header compilations passed")
