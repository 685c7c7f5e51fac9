# install() rules and the oas CMake package: find_package(oas) then gives oas::glsl,
# oas::pattern_c and oas::pattern (not with -DOAS_BUILD_CPP=OFF), plus OAS_GLSL_INCLUDE_DIR and
# OAS_SINGLE_GLSL.
# Headers, the GLSL library and the single-file include all land in <prefix>/include/oas/, so one
# include directory serves #include "oas/pattern.hpp" and #include "oas/oas.glsl" alike.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(OAS_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/oas)
set(installed_targets oas_glsl oas_pattern_c)
if(OAS_BUILD_CPP)
  list(APPEND installed_targets oas_pattern)
endif()
install(TARGETS ${installed_targets} EXPORT oasTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_SOURCE_DIR}/host/oas/oas_pattern.h
              ${PROJECT_SOURCE_DIR}/host/oas/pattern.hpp ${PROJECT_SOURCE_DIR}/host/oas/glsl_compat.hpp
              ${PROJECT_SOURCE_DIR}/host/oas/oa_columns.hpp ${PROJECT_SOURCE_DIR}/host/oas/baseline_columns.hpp
              ${OAS_GLSL_SOURCES} ${OAS_SINGLE_GLSL}
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/oas)
install(EXPORT oasTargets NAMESPACE oas:: DESTINATION ${OAS_CMAKE_INSTALL_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/oasConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/oasConfig.cmake
                              INSTALL_DESTINATION ${OAS_CMAKE_INSTALL_DIR}
                              PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
# 0.x: a minor version may change the samples (docs/PATTERN.md), so only the same minor matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/oasConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/oasConfig.cmake ${PROJECT_BINARY_DIR}/oasConfigVersion.cmake
        DESTINATION ${OAS_CMAKE_INSTALL_DIR})
# The C builder's source too, for FFI users who compile it into their own (shared) library.
# (With its header and oas_joe_kuo.inc, the Sobol table, so the directory compiles on its own.)
install(FILES ${PROJECT_SOURCE_DIR}/host/oas/oas_pattern.c ${PROJECT_SOURCE_DIR}/host/oas/oas_joe_kuo.inc
              ${PROJECT_SOURCE_DIR}/host/oas/oas_pattern.h
        DESTINATION ${CMAKE_INSTALL_DATADIR}/oas/src)
# Joe and Kuo's licence asks binary distributions to carry its notice: data/sobol/README.md has it.
install(FILES ${PROJECT_SOURCE_DIR}/docs/PATTERN.md ${PROJECT_SOURCE_DIR}/tests/golden/patterns.json
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/data/sobol/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR}
        RENAME SOBOL-DIRECTION-NUMBERS-LICENCE.md)

if(OAS_BUILD_TOOLS)
  # (oas-study stays in the build tree: it reads study/plot.py from the checkout.)
  install(TARGETS oas-samples oas-render oas-diff RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
