#pragma once
// Error handling for Vulkan calls. The check is never compiled out: a failed Vulkan call on a
// compute path means the results are garbage, so release builds must fail just as loudly.
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace oas::vk {

class VulkanError : public std::runtime_error {
public:
    explicit VulkanError(const std::string& what, VkResult result = VK_ERROR_UNKNOWN) : std::runtime_error(what), result_(result)
    {
    }
    VkResult result() const noexcept { return result_; }

private:
    VkResult result_;
};

// Thrown when no usable Vulkan instance or device exists, so tests can skip instead of failing.
class NoDeviceError : public VulkanError {
public:
    using VulkanError::VulkanError;
};

// "VK_ERROR_DEVICE_LOST" etc.; our own table so we do not depend on vk_enum_string_helper.h,
// which Debian's libvulkan-dev does not ship.
const char* resultName(VkResult r) noexcept;

[[noreturn]] void throwVkError(VkResult r, const char* callText, const char* file, int line);

}  // namespace oas::vk

#define OAS_VK_CHECK(call)                                                                                                       \
    do {                                                                                                                         \
        const VkResult oas_vk_check_result_ = (call);                                                                            \
        if (oas_vk_check_result_ != VK_SUCCESS) ::oas::vk::throwVkError(oas_vk_check_result_, #call, __FILE__, __LINE__);        \
    } while (0)
