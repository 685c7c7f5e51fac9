// Buffer: a host-visible Vulkan buffer, its memory and its texel views (host/vk/context.hpp).
#include "vk/context.hpp"

#include <fmt/format.h>

#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

namespace oas::vk {

Buffer::Buffer(Context& ctx, VkDeviceSize bytes) : ctx_(&ctx), size_(bytes)
{
    if (bytes == 0) throw std::invalid_argument("Buffer: size must be > 0");
    const VkDevice dev = ctx.device();
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = bytes;
    bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;  // group counts a kernel writes for the next (dispatchSequence)
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkBuffer buf = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreateBuffer(dev, &bci, nullptr, &buf));
    buffer_ = detail::Owned<VkBuffer>(buf, [dev](VkBuffer b) { vkDestroyBuffer(dev, b, nullptr); });
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(dev, buf, &req);

    // Host-visible device-local memory (unified memory, lavapipe, ReBAR) avoids staging copies; on
    // a discrete GPU it is a small BAR window, so fall back to plain host memory when it is full.
    const auto& mp = ctx.memoryProperties();
    const VkMemoryPropertyFlags need = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    std::vector<uint32_t> candidates;
    for (int pass = 0; pass < 2; ++pass)
        for (uint32_t i = 0; i < mp.memoryTypeCount; ++i) {
            const auto flags = mp.memoryTypes[i].propertyFlags;
            const bool local = flags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
            if ((req.memoryTypeBits & (1u << i)) && (flags & need) == need && local == (pass == 0) &&
                mp.memoryHeaps[mp.memoryTypes[i].heapIndex].size >= req.size)
                candidates.push_back(i);
        }
    if (candidates.empty()) throw VulkanError("Buffer: no HOST_VISIBLE|HOST_COHERENT memory type fits");

    VkResult last = VK_ERROR_OUT_OF_DEVICE_MEMORY;
    for (uint32_t type : candidates) {
        VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        mai.allocationSize = req.size;
        mai.memoryTypeIndex = type;
        VkDeviceMemory mem = VK_NULL_HANDLE;
        last = vkAllocateMemory(dev, &mai, nullptr, &mem);
        if (last == VK_ERROR_OUT_OF_DEVICE_MEMORY || last == VK_ERROR_OUT_OF_HOST_MEMORY) continue;
        if (last != VK_SUCCESS) throwVkError(last, "vkAllocateMemory", __FILE__, __LINE__);
        memory_ = detail::Owned<VkDeviceMemory>(mem, [dev](VkDeviceMemory m) { vkFreeMemory(dev, m, nullptr); });
        deviceLocal_ = mp.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        break;
    }
    if (memory_.get() == VK_NULL_HANDLE)
        throw VulkanError(fmt::format("Buffer: allocating {} bytes failed: {}", bytes, resultName(last)), last);
    OAS_VK_CHECK(vkBindBufferMemory(dev, buf, memory_.get(), 0));
    OAS_VK_CHECK(vkMapMemory(dev, memory_.get(), 0, VK_WHOLE_SIZE, 0, &mapped_));  // unmapped by vkFreeMemory
    std::memset(mapped_, 0, bytes);  // deterministic contents; freshly allocated memory is arbitrary
}

Buffer::Buffer(Buffer&& o) noexcept
    : ctx_(o.ctx_), size_(std::exchange(o.size_, 0)), mapped_(std::exchange(o.mapped_, nullptr)), deviceLocal_(o.deviceLocal_),
      memory_(std::move(o.memory_)), buffer_(std::move(o.buffer_)), uint4View_(std::move(o.uint4View_)),
      uintView_(std::move(o.uintView_))
{
}

Buffer::~Buffer()
{
    if (ctx_->broken()) uintView_.leak(), uint4View_.leak(), buffer_.leak(), memory_.leak();
}

VkBufferView Buffer::makeView(detail::Owned<VkBufferView>& slot, VkFormat format, VkDeviceSize texelBytes, const char* what)
{
    if (slot.get() != VK_NULL_HANDLE) return slot.get();
    const VkDeviceSize texels = size_ / texelBytes, limit = ctx_->limits().maxTexelBufferElements;
    if (size_ % texelBytes != 0 || texels > limit)
        throw std::invalid_argument(fmt::format("Buffer: {} bytes as a texel buffer of {} ({} texels): it must be a whole "
                                                "number of {}-byte texels, at most {} (the device's maxTexelBufferElements)",
                                                size_, what, size_ / double(texelBytes), texelBytes, limit));
    const VkDevice dev = ctx_->device();
    VkBufferViewCreateInfo vci{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    vci.buffer = buffer_.get();
    vci.format = format;
    vci.offset = 0;
    vci.range = VK_WHOLE_SIZE;
    VkBufferView view = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreateBufferView(dev, &vci, nullptr, &view));
    slot = detail::Owned<VkBufferView>(view, [dev](VkBufferView v) { vkDestroyBufferView(dev, v, nullptr); });
    return view;
}

// The spec requires both formats' support: R32G32B32A32_UINT for uniform texel buffers, R32_UINT
// for storage texel buffers.
VkBufferView Buffer::uint4View()
{
    return makeView(uint4View_, VK_FORMAT_R32G32B32A32_UINT, 16, "uvec4");
}

VkBufferView Buffer::uintView()
{
    return makeView(uintView_, VK_FORMAT_R32_UINT, 4, "uint");
}

}  // namespace oas::vk
