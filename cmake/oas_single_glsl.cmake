# cmake -DOAS_GLSL_ROOT=<shaders/oas> -DOAS_OUTPUT=<file> -DOAS_VERSION=<x.y.z> -P oas_single_glsl.cmake
# Writes oas.glsl with every `#include "file"` line replaced by that file (recursively, each file
# once: the files have include guards, so a repeat would be dead text). Only lines that start with
# #include are directives; the header's documentation mentions #include inside comments.
cmake_policy(VERSION 3.21)
foreach(var OAS_GLSL_ROOT OAS_OUTPUT OAS_VERSION)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "oas_single_glsl.cmake: -D${var}=... is required")
  endif()
endforeach()

set(oas_inlined "")
function(oas_inline file result)
  if(NOT EXISTS "${OAS_GLSL_ROOT}/${file}")
    message(FATAL_ERROR "oas_single_glsl.cmake: ${OAS_GLSL_ROOT}/${file} (included) does not exist")
  endif()
  file(READ "${OAS_GLSL_ROOT}/${file}" text)
  set(text "\n${text}")  # so that a directive on the first line also follows a newline
  string(REGEX MATCHALL "\n#include \"[^\"\n]+\"" directives "${text}")
  foreach(directive IN LISTS directives)
    string(REGEX REPLACE "^\n#include \"([^\"]+)\"$" "\\1" child "${directive}")
    string(STRIP "${directive}" line)
    if(child IN_LIST oas_inlined)
      set(body "// (${child} was inlined above)")
    else()
      list(APPEND oas_inlined "${child}")
      oas_inline("${child}" body)  # may add to oas_inlined in this scope
      set(body "// ---- ${child} ----\n${body}// ---- end of ${child} ----")
    endif()
    string(REPLACE "\n${line}\n" "\n${body}\n" text "${text}")
  endforeach()
  string(SUBSTRING "${text}" 1 -1 text)
  set(${result} "${text}" PARENT_SCOPE)
  set(oas_inlined "${oas_inlined}" PARENT_SCOPE)
endfunction()

oas_inline(oas.glsl single)
string(FIND "${single}" "\n#include" leftover)
if(NOT leftover EQUAL -1)
  message(FATAL_ERROR "oas_single_glsl.cmake: an #include survived inlining")
endif()
set(banner "// oas_single.glsl - oas ${OAS_VERSION}: shaders/oas/oas.glsl with its includes inlined, generated\n// by cmake/oas_single_glsl.cmake. Needs no #include support; otherwise the same library: read\n// the header below.\n")
# Write to a temporary file, then rename: a build interrupted mid-write leaves no half file.
file(WRITE "${OAS_OUTPUT}.tmp" "${banner}${single}")
file(RENAME "${OAS_OUTPUT}.tmp" "${OAS_OUTPUT}")
