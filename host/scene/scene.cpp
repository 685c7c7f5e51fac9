// The scene data model's methods, loading a scene file, and its summary (the format:
// scenes/README.md). The loader walks the JSON tree with the path of every node in hand, so each
// error names "file: json.path: value + valid range"; its sections live in the scene_*.cpp files
// named after them (scene_loader.hpp), the field readers in scene_fields.cpp.
#include "scene/scene.hpp"

#include <algorithm>
#include <cfloat>
#include <fstream>
#include <sstream>
#include <string_view>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "oas/oas_pattern.h"
#include "scene/scene_loader.hpp"

namespace oas::scene {

namespace fs = std::filesystem;
using detail::json;

SceneError::SceneError(std::string file, std::string jsonPath, const std::string& detail)
    : std::runtime_error(jsonPath.empty() ? fmt::format("{}: {}", file, detail)
                                          : fmt::format("{}: {}: {}", file, jsonPath, detail)),
      file_(std::move(file)), jsonPath_(std::move(jsonPath))
{
}

float Shape::area() const
{
    switch (type) {
    case Type::Sphere:
        return 4.0f * 3.14159265358979f * radius * radius;
    case Type::Quad:
        return glm::length(glm::cross(edgeU, edgeV));
    case Type::Triangle:
        return 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
    }
    return 0;
}

Aabb Shape::boundsAt(float time) const
{
    Aabb box;
    const glm::vec3 shift = velocity * time;
    switch (type) {
    case Type::Sphere:
        box.extend(center + shift - glm::vec3(radius));
        box.extend(center + shift + glm::vec3(radius));
        break;
    case Type::Quad:
        for (float a : {0.0f, 1.0f})
            for (float b : {0.0f, 1.0f}) box.extend(corner + shift + edgeU * a + edgeV * b);
        break;
    case Type::Triangle:
        box.extend(p0 + shift);
        box.extend(p1 + shift);
        box.extend(p2 + shift);
        break;
    }
    return box;
}

bool Scene::hasMotionBlur() const
{
    if (!(shutterClose > shutterOpen)) return false;
    return std::any_of(shapes.begin(), shapes.end(), [](const Shape& s) { return s.moves(); });
}

std::size_t Scene::areaLightCount() const
{
    return std::size_t(std::count_if(shapes.begin(), shapes.end(), [&](const Shape& s) { return isAreaLight(s); }));
}

int Scene::findMaterial(const std::string& materialName) const
{
    for (std::size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == materialName) return int(i);
    return -1;
}

const std::vector<std::string>& samplerNames()
{
    // The chooser, then the C builder's table in its order (the library's one list of names).
    static const std::vector<std::string> names = [] {
        std::vector<std::string> list = {"oa"};
        for (std::size_t i = 0; const std::uint32_t code = oas_construction_at(i); ++i)
            list.push_back(oas_construction_name(code));
        return list;
    }();
    return names;
}

bool samplerIsOrthogonalArray(const std::string& name)
{
    std::uint32_t code = 0;
    return name == "oa" || (oas_construction_from_name(name.c_str(), &code) == 0 && code < OAS_RANDOM);
}

namespace {

constexpr std::uintmax_t kMaxSceneBytes = std::uintmax_t(64) << 20;

}  // namespace

namespace detail {

Scene Loader::load(const json& root) const
{
    Scene scene;
    objectKeys(root, "", "the scene",
               {"version", "name", "resolution", "camera", "shutter", "environment", "materials", "shapes", "lights",
                "integrator", "sampler"});
    if (auto* v = find(root, "version")) {
        const std::uint32_t version = integer(*v, "version", 1, 1, "1");
        (void)version;
    }
    if (auto* v = find(root, "name")) scene.name = string(*v, "name");
    resolution(require(root, "", "resolution", "[width, height], integers 1..16384"), scene);
    scene.camera = camera(require(root, "", "camera", "an object (see scenes/README.md)"));
    if (auto* v = find(root, "shutter")) shutter(*v, scene);
    if (auto* v = find(root, "environment")) scene.environment = color(*v, "environment", 0, FLT_MAX);
    materials(require(root, "", "materials", "an array of materials"), scene);
    shapes(require(root, "", "shapes", "an array of shapes"), scene);
    if (auto* v = find(root, "lights")) lights(*v, scene);
    if (auto* v = find(root, "integrator")) scene.integrator = integrator(*v);
    if (auto* v = find(root, "sampler")) scene.sampler = sampler(*v);
    return scene;
}

}  // namespace detail

Scene parseScene(const std::string& jsonText, const fs::path& nameForMessages, const fs::path& baseDir)
{
    const std::string file = nameForMessages.string();
    const json root = detail::parseJson(jsonText, file);
    Scene scene = detail::Loader(file, baseDir).load(root);
    scene.path = nameForMessages;
    if (scene.name.empty()) scene.name = nameForMessages.stem().string();
    return scene;
}

Scene loadScene(const fs::path& file)
{
    std::error_code ec;
    const auto status = fs::status(file, ec);
    if (!fs::exists(status)) throw SceneError(file.string(), {}, "scene file not found (no such file)");
    if (fs::is_directory(status)) throw SceneError(file.string(), {}, "is a directory, not a scene file");
    // A device or FIFO (/dev/zero, a pipe) would be read without end or block forever.
    if (!fs::is_regular_file(status))
        throw SceneError(file.string(), {}, "is not a regular file (a device, FIFO or socket): valid a scene file");
    if (const auto size = fs::file_size(file, ec); !ec && size > kMaxSceneBytes)
        throw SceneError(
            file.string(), {},
            fmt::format("is {} bytes: valid scene files up to {} MiB (meshes go in OBJ files)", size, kMaxSceneBytes >> 20));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw SceneError(file.string(), {}, "cannot open the scene file for reading");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw SceneError(file.string(), {}, "error reading the scene file");
    fs::path base = file.parent_path();
    if (base.empty()) base = ".";
    return parseScene(text.str(), file, base);
}

std::string summary(const Scene& scene)
{
    std::string effects;
    auto add = [&](std::string_view e) {
        if (!effects.empty()) effects += ", ";
        effects += e;
    };
    add(scene.hasDepthOfField() ? "thin lens" : "pinhole");
    if (scene.hasMotionBlur()) add(fmt::format("motion blur [{}, {}]", scene.shutterOpen, scene.shutterClose));
    std::size_t triangles = 0;
    for (const auto& m : scene.meshes) triangles += m.triangles;
    const auto& it = scene.integrator;
    const std::string integrator =
        it.type == Integrator::Type::Direct
            ? std::string("direct lighting")
            : fmt::format("path tracing maxDepth {}{}{}{}", it.maxDepth, it.nextEventEstimation ? " NEE" : "",
                          it.mis ? "+MIS" : "",
                          it.rouletteStartDepth ? fmt::format(" RR from {}", it.rouletteStartDepth) : std::string());
    std::string sampler = fmt::format("{} {} spp", scene.sampler.name, scene.sampler.spp);
    if (samplerIsOrthogonalArray(scene.sampler.name)) sampler += " " + scene.sampler.offset;
    return fmt::format("{}: {}x{}, {}; {} shapes ({} mesh triangles), {} materials, {} area lights, {} point/spot "
                       "lights{}; {}; sampler {}",
                       scene.name, scene.width, scene.height, effects, scene.shapes.size(), triangles, scene.materials.size(),
                       scene.areaLightCount(), scene.lights.size(), scene.hasEnvironment() ? ", environment" : "", integrator,
                       sampler);
}

}  // namespace oas::scene
