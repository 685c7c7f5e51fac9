#pragma once
// Internal to host/scene: the loader, one member per section of the scene file. Each section's
// members are defined in the file named after it (scene_camera.cpp: resolution, camera, shutter;
// scene_materials.cpp; scene_shapes.cpp: shapes and OBJ meshes; scene_lights.cpp;
// scene_settings.cpp: integrator and sampler); load() in scene.cpp reads them in file order.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "scene/scene_fields.hpp"

namespace oas::scene::detail {

class Loader : private FieldReader {
public:
    /// Mesh paths in the scene are relative to baseDir.
    Loader(std::string file, std::filesystem::path baseDir) : FieldReader(std::move(file)), baseDir_(std::move(baseDir)) {}

    /// The whole scene from the parsed file (Scene::path and a default name are the caller's).
    Scene load(const json& root) const;

private:
    void resolution(const json& v, Scene& scene) const;
    Camera camera(const json& v) const;
    void shutter(const json& v, Scene& scene) const;
    void materials(const json& v, Scene& scene) const;
    /// The index of the material a shape names in "material".
    std::uint32_t materialRef(const json& shape, const std::string& p, const Scene& scene) const;
    void shapes(const json& v, Scene& scene) const;
    /// The renderer bounds a shape at shutter open and close; a velocity that carries it past the
    /// float range there would give infinite or NaN boxes (the loader checked positions at t = 0).
    void checkFiniteBounds(const Shape& shape, const Scene& scene, const std::string& path, std::string_view kind) const;
    /// One "mesh" entry of shapes[]: its OBJ file's triangles become shapes.
    void mesh(const json& s, const std::string& p, Scene& scene) const;
    void lights(const json& v, Scene& scene) const;
    Integrator integrator(const json& v) const;
    SamplerSpec sampler(const json& v) const;

    std::filesystem::path baseDir_;
};

}  // namespace oas::scene::detail
