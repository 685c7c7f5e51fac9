# Configures, builds and runs one example consumer project (examples/consumer-<MODE>) against this
# checkout, as another project would, in a scratch directory. Run by ctest (tests/CMakeLists.txt):
#   cmake -DMODE=find-package|add-subdirectory|fetchcontent -DOAS_SOURCE_DIR=<repo root>
#         -DOAS_BUILD_DIR=<built oas build dir> -DWORK_DIR=<scratch dir, wiped> -DGENERATOR=<generator>
#         [-DCXX_COMPILER=<path>] [-DC_COMPILER=<path>] -P run_consumer.cmake
# The consumer exits 77 without a Vulkan device; this script then prints its "SKIPPED: ..." line,
# which the test's SKIP_REGULAR_EXPRESSION turns into a skip (cmake -P cannot exit 77 itself).
foreach(var MODE OAS_SOURCE_DIR OAS_BUILD_DIR WORK_DIR GENERATOR)
  if("${${var}}" STREQUAL "")
    message(FATAL_ERROR "run_consumer.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT MODE MATCHES "^(find-package|add-subdirectory|fetchcontent)$")
  message(FATAL_ERROR "run_consumer.cmake: MODE must be find-package, add-subdirectory or fetchcontent, not '${MODE}'")
endif()

# Runs one step; on failure prints its merged output and stops, naming the step and its exit status.
# Sets step_rc and step_output in the caller; ALLOW_RC accepts one more exit status.
function(run_step name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "ALLOW_RC" "COMMAND")
  string(TIMESTAMP start "%s")
  execute_process(COMMAND ${arg_COMMAND} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  string(TIMESTAMP end "%s")
  math(EXPR seconds "${end} - ${start}")
  if(NOT rc STREQUAL "0" AND NOT (DEFINED arg_ALLOW_RC AND rc STREQUAL arg_ALLOW_RC))
    string(REPLACE ";" " " text "${arg_COMMAND}")
    message("${out}")  # verbatim: FATAL_ERROR would re-indent and re-wrap it
    message(FATAL_ERROR "consumer ${MODE}: ${name} failed (exit ${rc}) after ${seconds} s: ${text}")
  endif()
  message("consumer ${MODE}: ${name}: ${seconds} s")
  set(step_rc "${rc}" PARENT_SCOPE)
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(source "${OAS_SOURCE_DIR}/examples/consumer-${MODE}")
set(build "${WORK_DIR}/build")
# No build type: -O0 compiles oas and the consumer fastest, and oas must not impose its own.
set(configure_args -S "${source}" -B "${build}" -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=)
if(CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif()
if(C_COMPILER)
  list(APPEND configure_args "-DCMAKE_C_COMPILER=${C_COMPILER}")
endif()

if(MODE STREQUAL "find-package")
  set(prefix "${WORK_DIR}/prefix")
  if(NOT EXISTS "${OAS_BUILD_DIR}/cmake_install.cmake")
    message(FATAL_ERROR "consumer find-package: ${OAS_BUILD_DIR} is not a configured oas build")
  endif()
  # Installs what the main build has built: build it before running this test.
  run_step("install of ${OAS_BUILD_DIR}" COMMAND "${CMAKE_COMMAND}" --install "${OAS_BUILD_DIR}" --prefix "${prefix}")
  list(APPEND configure_args "-DCMAKE_PREFIX_PATH=${prefix}")
elseif(MODE STREQUAL "add-subdirectory")
  list(APPEND configure_args "-DOAS_SOURCE_DIR=${OAS_SOURCE_DIR}")
else()
  find_program(GIT_EXECUTABLE git)
  set(rc 1)
  if(GIT_EXECUTABLE)
    execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${OAS_SOURCE_DIR}" rev-parse HEAD
                    RESULT_VARIABLE rc OUTPUT_VARIABLE commit ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
  endif()
  if(rc STREQUAL "0")
    # FetchContent clones the commit, so what is not committed is not tested: say so.
    execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${OAS_SOURCE_DIR}" status --porcelain
                    OUTPUT_VARIABLE dirty OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(dirty)
      message("consumer fetchcontent: note: testing commit ${commit}; the checkout's uncommitted changes are not in it")
    endif()
    list(APPEND configure_args "-DOAS_GIT_REPOSITORY=${OAS_SOURCE_DIR}" "-DOAS_GIT_TAG=${commit}")
  else()
    # A source tree without git (an exported tarball, a CI that copies files): FetchContent takes an
    # archive of it instead, which is the same download-and-add path with URL in place of git.
    # What a subproject build reads: the top-level CMakeLists.txt, cmake/, host/ and shaders/.
    set(archive "${WORK_DIR}/oas-source.tar.gz")
    run_step("archive of ${OAS_SOURCE_DIR}" COMMAND "${CMAKE_COMMAND}" -E chdir "${OAS_SOURCE_DIR}"
             "${CMAKE_COMMAND}" -E tar czf "${archive}" CMakeLists.txt cmake host shaders)
    message("consumer fetchcontent: note: ${OAS_SOURCE_DIR} is not a git checkout (or git is missing); fetching an archive of it")
    list(APPEND configure_args "-DOAS_URL=file://${archive}")
  endif()
endif()

run_step("configure" COMMAND "${CMAKE_COMMAND}" ${configure_args})
run_step("build" COMMAND "${CMAKE_COMMAND}" --build "${build}" -j 2)

# Multi-config generators put the program under the default configuration's folder.
set(program "${build}/consumer")
if(NOT EXISTS "${program}" AND EXISTS "${build}/Debug/consumer")
  set(program "${build}/Debug/consumer")
endif()
run_step("run" COMMAND "${program}" ALLOW_RC 77)
message("${step_output}")
