#include "view/presenter.hpp"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

namespace oas::view {

using vk::detail::Owned;

struct Presenter::Impl {
    vk::Context& ctx;
    GLFWwindow* window;
    Owned<VkSurfaceKHR> surface;
    Owned<VkSwapchainKHR> swapchain;
    VkFormat format = VK_FORMAT_UNDEFINED;
    bool bgr = true;  ///< B8G8R8A8 (else R8G8B8A8)
    VkExtent2D extent{0, 0};
    std::vector<VkImage> images;
    std::vector<Owned<VkSemaphore>> renderDone;  ///< one per swapchain image: present waits on it
    Owned<VkSemaphore> acquired;
    Owned<VkFence> fence;
    Owned<VkCommandPool> pool;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    std::unique_ptr<vk::Buffer> upload, download;
    bool stale = true;      ///< the swapchain must be (re)made before the next frame
    bool madeOnce = false;  ///< a swapchain existed before: the next one is a recreation

    Impl(vk::Context& c, GLFWwindow* w) : ctx(c), window(w)
    {
        const VkDevice dev = ctx.device();
        makeSurface();
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore s = VK_NULL_HANDLE;
        OAS_VK_CHECK(vkCreateSemaphore(dev, &sci, nullptr, &s));
        acquired = Owned<VkSemaphore>(s, [dev](VkSemaphore h) { vkDestroySemaphore(dev, h, nullptr); });
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence f = VK_NULL_HANDLE;
        OAS_VK_CHECK(vkCreateFence(dev, &fci, nullptr, &f));
        fence = Owned<VkFence>(f, [dev](VkFence h) { vkDestroyFence(dev, h, nullptr); });
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = ctx.queueFamily();
        VkCommandPool p = VK_NULL_HANDLE;
        OAS_VK_CHECK(vkCreateCommandPool(dev, &pci, nullptr, &p));
        pool = Owned<VkCommandPool>(p, [dev](VkCommandPool h) { vkDestroyCommandPool(dev, h, nullptr); });
        VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        cai.commandPool = p;
        cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        cai.commandBufferCount = 1;
        OAS_VK_CHECK(vkAllocateCommandBuffers(dev, &cai, &cmd));
    }

    ~Impl()
    {
        // Nothing may be destroyed while the queue still uses it (the owned handles then go in
        // reverse declaration order: buffers, pool, fence, semaphores, swapchain, surface).
        if (ctx.device() != VK_NULL_HANDLE && !ctx.broken()) vkDeviceWaitIdle(ctx.device());
        download.reset();
        upload.reset();
        pool.reset();
        renderDone.clear();
        swapchain.reset();
        surface.reset();
    }

    void makeSurface()
    {
        const VkInstance inst = ctx.instance();
        VkSurfaceKHR s = VK_NULL_HANDLE;
        OAS_VK_CHECK(glfwCreateWindowSurface(inst, window, nullptr, &s));
        surface = Owned<VkSurfaceKHR>(s, [inst](VkSurfaceKHR h) { vkDestroySurfaceKHR(inst, h, nullptr); });
        VkBool32 supported = VK_FALSE;
        OAS_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice(), ctx.queueFamily(), s, &supported));
        if (!supported)
            throw vk::VulkanError("the window's surface cannot be presented from queue family " +
                                  std::to_string(ctx.queueFamily()) + " of " + ctx.deviceName());
    }

    /// (Re)creates the swapchain for the window's current size; false while the window is 0 x 0.
    bool makeSwapchain()
    {
        const VkDevice dev = ctx.device();
        const VkPhysicalDevice pd = ctx.physicalDevice();
        vkDeviceWaitIdle(dev);
        VkSurfaceCapabilitiesKHR caps;
        OAS_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface.get(), &caps));
        VkExtent2D want = caps.currentExtent;
        if (want.width == std::numeric_limits<std::uint32_t>::max()) {  // the surface takes any size
            int w = 0, h = 0;
            glfwGetFramebufferSize(window, &w, &h);
            want.width = std::clamp(std::uint32_t(std::max(w, 0)), caps.minImageExtent.width, caps.maxImageExtent.width);
            want.height = std::clamp(std::uint32_t(std::max(h, 0)), caps.minImageExtent.height, caps.maxImageExtent.height);
        }
        if (want.width == 0 || want.height == 0) return false;  // minimised
        const VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        if ((caps.supportedUsageFlags & usage) != usage)
            throw vk::VulkanError("the window's swapchain images cannot be transfer source and destination on " +
                                  ctx.deviceName() + " (oas-view copies its frames in and back out)");

        std::uint32_t n = 0;
        OAS_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface.get(), &n, nullptr));
        std::vector<VkSurfaceFormatKHR> formats(n);
        OAS_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface.get(), &n, formats.data()));
        // Our bytes are already sRGB-encoded (linearToSrgb8), and a buffer-to-image copy moves bytes
        // unchanged whatever the format's encoding: any 8-bit BGRA/RGBA format shows them as meant.
        const VkFormat preferred[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                                      VK_FORMAT_R8G8B8A8_SRGB};
        VkSurfaceFormatKHR chosen{VK_FORMAT_UNDEFINED, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};
        for (VkFormat f : preferred) {
            auto it = std::find_if(formats.begin(), formats.end(), [&](const VkSurfaceFormatKHR& sf) {
                return sf.format == f && sf.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
            });
            if (it != formats.end()) {
                chosen = *it;
                break;
            }
        }
        if (chosen.format == VK_FORMAT_UNDEFINED)
            throw vk::VulkanError("the window's surface offers no 8-bit BGRA or RGBA sRGB format on " + ctx.deviceName());
        format = chosen.format;
        bgr = format == VK_FORMAT_B8G8R8A8_UNORM || format == VK_FORMAT_B8G8R8A8_SRGB;

        VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
        ci.surface = surface.get();
        ci.minImageCount = caps.maxImageCount ? std::min(caps.minImageCount + 1, caps.maxImageCount) : caps.minImageCount + 1;
        ci.imageFormat = chosen.format;
        ci.imageColorSpace = chosen.colorSpace;
        ci.imageExtent = want;
        ci.imageArrayLayers = 1;
        ci.imageUsage = usage;
        ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
        ci.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                              ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                              : caps.currentTransform;
        ci.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                                ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                                : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
        ci.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always supported
        ci.clipped = VK_TRUE;
        ci.oldSwapchain = swapchain.get();
        VkSwapchainKHR sc = VK_NULL_HANDLE;
        OAS_VK_CHECK(vkCreateSwapchainKHR(dev, &ci, nullptr, &sc));
        renderDone.clear();
        swapchain = Owned<VkSwapchainKHR>(sc, [dev](VkSwapchainKHR h) { vkDestroySwapchainKHR(dev, h, nullptr); });
        extent = want;
        OAS_VK_CHECK(vkGetSwapchainImagesKHR(dev, sc, &n, nullptr));
        images.resize(n);
        OAS_VK_CHECK(vkGetSwapchainImagesKHR(dev, sc, &n, images.data()));
        for (std::uint32_t i = 0; i < n; ++i) {
            VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
            VkSemaphore s = VK_NULL_HANDLE;
            OAS_VK_CHECK(vkCreateSemaphore(dev, &sci, nullptr, &s));
            renderDone.emplace_back(s, [dev](VkSemaphore h) { vkDestroySemaphore(dev, h, nullptr); });
        }
        const VkDeviceSize bytes = VkDeviceSize(want.width) * want.height * 4;
        upload = std::make_unique<vk::Buffer>(ctx, bytes);
        download = std::make_unique<vk::Buffer>(ctx, bytes);
        stale = false;
        return true;
    }

    /// Recovers from an acquire/present result; true when the frame may go on.
    bool handle(VkResult r, const char* what)
    {
        if (r == VK_SUCCESS) return true;
        if (r == VK_SUBOPTIMAL_KHR) {  // still presentable; rebuilt before the next frame
            stale = true;
            return true;
        }
        if (r == VK_ERROR_OUT_OF_DATE_KHR) {
            stale = true;
            return false;
        }
        if (r == VK_ERROR_SURFACE_LOST_KHR) {
            vkDeviceWaitIdle(ctx.device());
            renderDone.clear();
            swapchain.reset();
            surface.reset();
            makeSurface();
            stale = true;
            return false;
        }
        vk::throwVkError(r, what, __FILE__, __LINE__);
    }
};

Presenter::Presenter(vk::Context& context, GLFWwindow* window) : impl_(std::make_unique<Impl>(context, window)) {}

Presenter::~Presenter() = default;

bool Presenter::present(const Frame& frame, bool readBack)
{
    Impl& m = *impl_;
    if (m.stale) {
        if (!m.makeSwapchain()) return false;
        if (m.madeOnce) ++recreations_;
        m.madeOnce = true;
    }
    const VkDevice dev = m.ctx.device();
    std::uint32_t index = 0;
    if (!m.handle(vkAcquireNextImageKHR(dev, m.swapchain.get(), std::numeric_limits<std::uint64_t>::max(), m.acquired.get(),
                                        VK_NULL_HANDLE, &index),
                  "vkAcquireNextImageKHR"))
        return false;

    // The frame at the top-left, dark grey around it, in the swapchain's byte order.
    const std::uint32_t w = m.extent.width, h = m.extent.height;
    auto* dst = static_cast<std::uint8_t*>(m.upload->data());
    const int r = m.bgr ? 2 : 0, b = m.bgr ? 0 : 2;
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            std::uint8_t* p = dst + (std::size_t(y) * w + x) * 4;
            if (x < frame.width && y < frame.height) {
                const std::uint8_t* s = frame.at(x, y);
                p[r] = s[0], p[1] = s[1], p[b] = s[2];
            } else {
                p[0] = p[1] = p[2] = 24;
            }
            p[3] = 255;
        }

    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    OAS_VK_CHECK(vkResetCommandBuffer(m.cmd, 0));
    OAS_VK_CHECK(vkBeginCommandBuffer(m.cmd, &bi));
    auto barrier = [&](VkImageLayout from, VkImageLayout to, VkAccessFlags src, VkAccessFlags dstAccess,
                       VkPipelineStageFlags srcStage, VkPipelineStageFlags dstStage) {
        VkImageMemoryBarrier ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        ib.srcAccessMask = src;
        ib.dstAccessMask = dstAccess;
        ib.oldLayout = from;
        ib.newLayout = to;
        ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.image = m.images[index];
        ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdPipelineBarrier(m.cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &ib);
    };
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {w, h, 1};
    barrier(VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    vkCmdCopyBufferToImage(m.cmd, m.upload->handle(), m.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    VkImageLayout layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    VkAccessFlags lastAccess = VK_ACCESS_TRANSFER_WRITE_BIT;
    if (readBack) {
        barrier(layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        vkCmdCopyImageToBuffer(m.cmd, m.images[index], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, m.download->handle(), 1, &region);
        VkBufferMemoryBarrier bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
        bb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        bb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        bb.buffer = m.download->handle();
        bb.size = VK_WHOLE_SIZE;
        vkCmdPipelineBarrier(m.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &bb, 0,
                             nullptr);
        layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        lastAccess = VK_ACCESS_TRANSFER_READ_BIT;
    }
    barrier(layout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, lastAccess, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    OAS_VK_CHECK(vkEndCommandBuffer(m.cmd));

    const VkSemaphore acquired = m.acquired.get(), done = m.renderDone[index].get();
    const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &acquired;
    si.pWaitDstStageMask = &waitStage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &m.cmd;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &done;
    const VkFence fence = m.fence.get();
    OAS_VK_CHECK(vkResetFences(dev, 1, &fence));
    OAS_VK_CHECK(vkQueueSubmit(m.ctx.queue(), 1, &si, fence));
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &done;
    pi.swapchainCount = 1;
    const VkSwapchainKHR sc = m.swapchain.get();
    pi.pSwapchains = &sc;
    pi.pImageIndices = &index;
    const VkResult presented = vkQueuePresentKHR(m.ctx.queue(), &pi);
    // The copy is tiny; waiting here keeps one frame in flight, so the staging buffers and the
    // acquire semaphore are free again when present() returns.
    OAS_VK_CHECK(vkWaitForFences(dev, 1, &fence, VK_TRUE, std::numeric_limits<std::uint64_t>::max()));
    if (readBack) {
        shown_.resize(w, h);
        const auto* src = static_cast<const std::uint8_t*>(m.download->data());
        for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
            shown_.rgb[i * 3 + 0] = src[i * 4 + r];
            shown_.rgb[i * 3 + 1] = src[i * 4 + 1];
            shown_.rgb[i * 3 + 2] = src[i * 4 + b];
        }
    }
    m.handle(presented, "vkQueuePresentKHR");
    return true;
}

}  // namespace oas::view
