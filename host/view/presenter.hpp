#pragma once
// Showing CPU-made RGB8 frames in a GLFW window through a Vulkan swapchain, on the compute
// context's own device and queue (oas-view). Each frame is one buffer-to-image copy into the
// acquired swapchain image (no graphics pipeline: lavapipe and every GPU support transfer-dst
// swapchain images), optionally followed by a copy back out of the same image, which is how
// --screenshot reads exactly what the window shows. One frame in flight: present() waits for its
// copy to finish, so the CPU-side buffers can be reused at once.
//
// Robustness: an out-of-date or suboptimal swapchain (resize) is recreated; a zero-sized
// (minimised) window skips frames; a lost surface (VK_ERROR_SURFACE_LOST_KHR) is recreated from
// the window. RAII owns every handle; destruction waits for the device first.
#include <cstdint>
#include <memory>
#include <vector>

#include "vk/context.hpp"

struct GLFWwindow;

namespace oas::view {

/// An RGB8 picture, row-major, top row first, 3 bytes per pixel.
struct Frame {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
    void resize(std::uint32_t w, std::uint32_t h, std::uint8_t fill = 0)
    {
        width = w;
        height = h;
        rgb.assign(std::size_t(w) * h * 3, fill);
    }
    std::uint8_t* at(std::uint32_t x, std::uint32_t y) { return rgb.data() + (std::size_t(y) * width + x) * 3; }
    const std::uint8_t* at(std::uint32_t x, std::uint32_t y) const { return rgb.data() + (std::size_t(y) * width + x) * 3; }
};

class Presenter {
public:
    /// The context must have been made with the window system's instance extensions, the
    /// swapchain device extension and a queue family that can present (see ContextOptions).
    Presenter(vk::Context& context, GLFWwindow* window);
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    /// Shows `frame` at the window's top-left corner (the rest dark grey; a larger frame is
    /// clipped). With readBack, the swapchain image is copied back after the frame is written
    /// into it: lastShown() then holds the window's content. Returns false when nothing was
    /// shown (minimised, or the swapchain had to be recreated first: call again next frame).
    bool present(const Frame& frame, bool readBack = false);
    /// The window's content at the last present(…, true).
    const Frame& lastShown() const { return shown_; }
    /// How many times the swapchain (or surface) was recreated, for tests and the log.
    std::uint32_t recreations() const { return recreations_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    Frame shown_;
    std::uint32_t recreations_ = 0;
};

}  // namespace oas::view
