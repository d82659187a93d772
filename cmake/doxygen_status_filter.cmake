# Doxygen input filter for status.h: Doxygen's preprocessor does not expand
# the X-macro that generates the status enum, so this writes the enumerators
# out, each with its description, on the line of the X-macro use (line
# numbers stay as they are). Other files pass through unchanged.
#
#   cmake -DOUT=<scratch file> -P doxygen_status_filter.cmake <file>
cmake_minimum_required(VERSION 3.16)

# The file to filter is the last argument.
math(EXPR last "${CMAKE_ARGC} - 1")
set(input "${CMAKE_ARGV${last}}")
file(READ "${input}" text)
set(use "BRDFFIT_STATUS_LIST(BRDFFIT_STATUS_ENUM_ENTRY_)")
string(FIND "${text}" "${use}" at)
if(NOT at EQUAL -1)
  string(REGEX MATCHALL "X\\((BRDFFIT_[A-Z0-9_]+), ([0-9]+), \"([^\"]*)\"\\)" entries "${text}")
  set(expanded "")
  foreach(entry ${entries})
    string(REGEX REPLACE "X\\((BRDFFIT_[A-Z0-9_]+), ([0-9]+), \"([^\"]*)\"\\)"
      "\\1 = \\2, /**< \\3 */ " entry "${entry}")
    string(APPEND expanded "${entry}")
  endforeach()
  string(REPLACE "${use}" "${expanded}" text "${text}")
endif()
file(WRITE "${OUT}" "${text}")
execute_process(COMMAND ${CMAKE_COMMAND} -E cat "${OUT}")
