#include "vk/check.hpp"

#include <fmt/format.h>

namespace oas::vk {

const char* resultName(VkResult r) noexcept
{
    switch (r) {
#define OAS_VK_RESULT_CASE(x)                                                                                                    \
    case x:                                                                                                                      \
        return #x;
        OAS_VK_RESULT_CASE(VK_SUCCESS)
        OAS_VK_RESULT_CASE(VK_NOT_READY)
        OAS_VK_RESULT_CASE(VK_TIMEOUT)
        OAS_VK_RESULT_CASE(VK_EVENT_SET)
        OAS_VK_RESULT_CASE(VK_EVENT_RESET)
        OAS_VK_RESULT_CASE(VK_INCOMPLETE)
        OAS_VK_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        OAS_VK_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        OAS_VK_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
        OAS_VK_RESULT_CASE(VK_ERROR_DEVICE_LOST)
        OAS_VK_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        OAS_VK_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        OAS_VK_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        OAS_VK_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        OAS_VK_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        OAS_VK_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        OAS_VK_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        OAS_VK_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
        OAS_VK_RESULT_CASE(VK_ERROR_UNKNOWN)
        OAS_VK_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        OAS_VK_RESULT_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        OAS_VK_RESULT_CASE(VK_ERROR_FRAGMENTATION)
        OAS_VK_RESULT_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        OAS_VK_RESULT_CASE(VK_PIPELINE_COMPILE_REQUIRED)
        OAS_VK_RESULT_CASE(VK_ERROR_SURFACE_LOST_KHR)
        OAS_VK_RESULT_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        OAS_VK_RESULT_CASE(VK_SUBOPTIMAL_KHR)
        OAS_VK_RESULT_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        OAS_VK_RESULT_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
        OAS_VK_RESULT_CASE(VK_ERROR_INVALID_SHADER_NV)
#undef OAS_VK_RESULT_CASE
    default:
        return "VK_RESULT_UNRECOGNISED";
    }
}

void throwVkError(VkResult r, const char* callText, const char* file, int line)
{
    const std::string msg =
        fmt::format("Vulkan call failed: {} returned {} ({}) at {}:{}", callText, resultName(r), static_cast<int>(r), file, line);
    throw VulkanError(msg, r);
}

}  // namespace oas::vk
