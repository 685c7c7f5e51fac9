# What every consumer does once it has oas (oas::pattern and OAS_GLSL_INCLUDE_DIR): compile its own
# shader against the GLSL library into a C header, and build the host program that dispatches it.
find_package(Vulkan REQUIRED)
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
if(NOT OAS_GLSL_INCLUDE_DIR)
  message(FATAL_ERROR "OAS_GLSL_INCLUDE_DIR is not set: oas was not found or is too old")
endif()

set(consumer_spv ${CMAKE_CURRENT_BINARY_DIR}/consumer_spv.h)
add_custom_command(
  OUTPUT ${consumer_spv}
  COMMAND ${GLSLANG_VALIDATOR} --target-env vulkan1.1 -I${OAS_GLSL_INCLUDE_DIR}
          --depfile ${consumer_spv}.d --vn consumer_spv -o ${consumer_spv} ${CMAKE_CURRENT_LIST_DIR}/consumer.comp
  DEPENDS ${CMAKE_CURRENT_LIST_DIR}/consumer.comp
  DEPFILE ${consumer_spv}.d  # edits to the #included library files rebuild the shader too
  VERBATIM)

add_executable(consumer ${CMAKE_CURRENT_LIST_DIR}/consumer.cpp ${consumer_spv})
target_include_directories(consumer PRIVATE ${CMAKE_CURRENT_BINARY_DIR})
target_link_libraries(consumer PRIVATE oas::pattern Vulkan::Vulkan)
