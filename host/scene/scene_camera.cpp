// The image and the view: "resolution", "camera" and "shutter".
#include <cfloat>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "scene/scene_loader.hpp"

namespace oas::scene::detail {

void Loader::resolution(const json& v, Scene& scene) const
{
    if (!v.is_array() || v.size() != 2) typeError(v, "resolution", "[width, height]", "two integers 1 .. 16384");
    scene.width = integer(v[0], "resolution[0]", 1, kMaxResolution, "1 .. 16384 pixels");
    scene.height = integer(v[1], "resolution[1]", 1, kMaxResolution, "1 .. 16384 pixels");
}

Camera Loader::camera(const json& v) const
{
    const std::string p = "camera";
    objectKeys(v, p, "the camera", {"type", "position", "lookAt", "up", "fovY", "apertureRadius", "focusDistance"});
    Camera cam;
    std::string type;
    if (auto* t = find(v, "type")) type = choice(*t, child(p, "type"), {"pinhole", "thinlens"});
    cam.position = vec3(require(v, p, "position", "[x, y, z]"), child(p, "position"));
    cam.lookAt = vec3(require(v, p, "lookAt", "[x, y, z], a point other than position"), child(p, "lookAt"));
    const glm::vec3 axis = cam.lookAt - cam.position;
    if (!(glm::length(axis) > 0))
        fail(child(p, "lookAt"), fmt::format("{} equals the camera position: valid any other point", show(cam.lookAt)));
    if (!std::isfinite(glm::length(axis)))
        fail(child(p, "lookAt"), fmt::format("lookAt {} - position {} overflows 32-bit floats (|lookAt - position| "
                                             "must be < 3.4e38): valid closer points",
                                             show(cam.lookAt), show(cam.position)));
    if (auto* u = find(v, "up")) cam.up = vec3(*u, child(p, "up"));
    // Written so that NaN (an up vector whose length overflows) fails too.
    if (!(glm::length(cam.up) > 0 && std::isfinite(glm::length(cam.up))) ||
        !(glm::length(glm::cross(glm::normalize(axis), glm::normalize(cam.up))) >= 1e-6f))
        fail(child(p, "up"),
             fmt::format("{} is zero, too long for 32-bit floats, or parallel to the view direction {}: valid a vector not "
                         "parallel to lookAt - position",
                         show(cam.up), show(axis)));
    cam.fovYDegrees = realIn(require(v, p, "fovY", "degrees in (0, 180)"), child(p, "fovY"), 0, 180,
                             "(0, 180) degrees (full vertical angle)", true, true);
    if (auto* a = find(v, "apertureRadius"))
        cam.apertureRadius = realIn(*a, child(p, "apertureRadius"), 0, FLT_MAX, ">= 0 (world units; 0 = pinhole)");
    if (type == "pinhole" && cam.apertureRadius > 0)
        fail(child(p, "apertureRadius"), fmt::format("{} on a pinhole camera: valid 0 for \"pinhole\" (use type "
                                                     "\"thinlens\" for depth of field)",
                                                     cam.apertureRadius));
    if (type == "thinlens" && !(cam.apertureRadius > 0))
        fail(child(p, "apertureRadius"),
             fmt::format("{} on a thin-lens camera: valid > 0 (world units; use type \"pinhole\" for none)", cam.apertureRadius));
    cam.thinLens = cam.apertureRadius > 0;
    cam.focusDistance = glm::length(axis);
    if (auto* f = find(v, "focusDistance"))
        cam.focusDistance = realIn(*f, child(p, "focusDistance"), 0, FLT_MAX, "> 0 (world units)", true);
    return cam;
}

void Loader::shutter(const json& v, Scene& scene) const
{
    objectKeys(v, "shutter", "the shutter", {"open", "close"});
    if (auto* o = find(v, "open")) scene.shutterOpen = real(*o, "shutter.open");
    if (auto* c = find(v, "close")) scene.shutterClose = real(*c, "shutter.close");
    if (scene.shutterClose < scene.shutterOpen)
        fail("shutter.close",
             fmt::format("{} is before shutter.open {}: valid close >= open", scene.shutterClose, scene.shutterOpen));
}

}  // namespace oas::scene::detail
