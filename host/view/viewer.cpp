#include "view/viewer.hpp"

#include <filesystem>
#include <sstream>

#include "image/image.hpp"
#include "oas/atomic_file.hpp"
#include "oas/pattern.hpp"

namespace oas::view {

std::string glfwMessage()
{
    const char* text = nullptr;
    const int code = glfwGetError(&text);
    return code == GLFW_NO_ERROR ? std::string("no GLFW error reported") : std::string(text ? text : "unknown");
}

std::vector<ScriptedKey> parseScript(const std::string& text)
{
    std::vector<ScriptedKey> keys;
    std::istringstream in(text);
    std::string token;
    std::uint32_t frame = 1;
    while (in >> token) {
        std::string name = token;
        const auto at = token.find('@');
        if (at != std::string::npos) {
            name = token.substr(0, at);
            const std::string number = token.substr(at + 1);
            if (number.empty() || number.size() > 6 || number.find_first_not_of("0123456789") != std::string::npos)
                throw UsageError("--script: '" + token + "': the frame after @ must be a number 0 .. 999999");
            frame = std::uint32_t(std::stoul(number));
        }
        ScriptedKey k{0, false, frame};
        if (name == "esc") {
            k.key = GLFW_KEY_ESCAPE;
        } else if (name.size() == 1) {
            const char c = name[0];
            if (c >= 'a' && c <= 'z')
                k.key = GLFW_KEY_A + (c - 'a');
            else if (c >= 'A' && c <= 'Z')
                k.key = GLFW_KEY_A + (c - 'A'), k.shift = true;
            else if (c == '+')
                k.key = GLFW_KEY_EQUAL, k.shift = true;
            else if (c == '-')
                k.key = GLFW_KEY_MINUS;
            else if (c == ']')
                k.key = GLFW_KEY_RIGHT_BRACKET;
            else if (c == '[')
                k.key = GLFW_KEY_LEFT_BRACKET;
            else if (c == '.')
                k.key = GLFW_KEY_PERIOD;
        }
        if (k.key == 0)
            throw UsageError("--script: unknown key '" + name + "' (valid: a letter, + - ] [ . or esc, e.g. \"s@3 r@5\")");
        keys.push_back(k);
    }
    return keys;
}

std::vector<std::string> samplerCycle()
{
    std::vector<std::string> names = samplerNames();
    names.push_back("oa");
    return names;
}

const std::vector<std::string> kOffsets = {"cmj", "mj", "j", "centered"};

std::string cycled(const std::vector<std::string>& list, const std::string& current, int step)
{
    auto it = std::find(list.begin(), list.end(), current);
    const int n = int(list.size());
    const int i = it == list.end() ? 0 : int(it - list.begin());
    return list[std::size_t(((i + step) % n + n) % n)];
}

std::uint32_t nextCount(const std::string& sampler, std::uint32_t strength, std::uint32_t dims, std::uint32_t current, bool up)
{
    try {
        if (up) {
            const std::uint32_t lo = std::min(current * 2, kMaxSamples);
            const auto c = validCounts(sampler, strength, dims, lo, std::min(lo * 2 + 16, kMaxSamples));
            return c.empty() ? current : c.front();
        }
        if (current < 2) return current;
        const auto c = validCounts(sampler, strength, dims, std::max(1u, current / 8), current / 2);
        return c.empty() ? current : c.back();
    } catch (const InvalidArgument&) {
        return current;
    }
}

Viewer::Viewer(std::uint32_t width, std::uint32_t height, const std::string& title)
{
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_ = glfwCreateWindow(int(width), int(height), title.c_str(), nullptr, nullptr);
    if (!window_) throw std::runtime_error("cannot open a window: " + glfwMessage());
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
        if (action == GLFW_PRESS || action == GLFW_REPEAT)
            static_cast<Viewer*>(glfwGetWindowUserPointer(w))->pending_.push_back({key, (mods & GLFW_MOD_SHIFT) != 0, 0});
    });
    vk::ContextOptions options;
    std::uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names) throw std::runtime_error("GLFW found no Vulkan surface support: " + glfwMessage());
    for (std::uint32_t i = 0; i < count; ++i) options.instanceExtensions.push_back(names[i]);
    options.deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    options.canPresent = [](VkInstance instance, VkPhysicalDevice device, std::uint32_t family) {
        return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
    };
    context_ = std::make_unique<vk::Context>(options);
    presenter_ = std::make_unique<Presenter>(*context_, window_);
}

Viewer::~Viewer()
{
    presenter_.reset();
    if (window_) glfwDestroyWindow(window_);
}

std::vector<ScriptedKey> Viewer::keys(std::vector<ScriptedKey>& script, std::uint32_t frame)
{
    glfwPollEvents();
    std::vector<ScriptedKey> out;
    for (auto it = script.begin(); it != script.end();)
        if (it->frame <= frame) {
            out.push_back(*it);
            it = script.erase(it);
        } else {
            ++it;
        }
    out.insert(out.end(), pending_.begin(), pending_.end());
    pending_.clear();
    return out;
}

void writeScreenshot(const std::string& path, const Frame& frame)
{
    if (const auto parent = std::filesystem::path(path).parent_path(); !parent.empty())
        std::filesystem::create_directories(parent);
    writeFileAtomically(path, image::encodePngRgb8(frame.width, frame.height, frame.rgb));
    std::printf("wrote %s (%ux%u, the window's content)\n", path.c_str(), frame.width, frame.height);
}

}  // namespace oas::view
