// "materials", and the shapes' references to them by name.
#include <cfloat>

#include <fmt/format.h>

#include "scene/scene_loader.hpp"

namespace oas::scene::detail {

void Loader::materials(const json& v, Scene& scene) const
{
    forEachObject(v, "materials", "material", [&](const json& m, const std::string& p) {
        Material mat;
        std::string type = "diffuse";
        if (auto* t = find(m, "type")) type = choice(*t, child(p, "type"), {"diffuse", "conductor", "dielectric"});
        if (type == "diffuse") {
            mat.type = Material::Type::Diffuse;
            objectKeys(m, p, "a diffuse material", {"name", "type", "albedo", "emission"});
            mat.albedo = glm::vec3(0.8f);
        } else if (type == "conductor") {
            mat.type = Material::Type::Conductor;
            objectKeys(m, p, "a conductor material", {"name", "type", "albedo", "roughness", "emission"});
            mat.albedo = glm::vec3(0.9f);
        } else {
            mat.type = Material::Type::Dielectric;
            objectKeys(m, p, "a dielectric material", {"name", "type", "albedo", "roughness", "ior", "emission"});
            mat.albedo = glm::vec3(1.0f);
        }
        mat.name = string(require(m, p, "name", "a unique non-empty string"), child(p, "name"));
        if (mat.name.empty()) fail(child(p, "name"), "\"\" is not valid: valid a unique non-empty string");
        if (int prev = scene.findMaterial(mat.name); prev >= 0)
            fail(child(p, "name"),
                 fmt::format("\"{}\" is already the name of materials[{}]: valid a unique name", mat.name, prev));
        if (auto* a = find(m, "albedo")) mat.albedo = color(*a, child(p, "albedo"), 0, 1);
        if (auto* r = find(m, "roughness"))
            mat.roughness = realIn(*r, child(p, "roughness"), 0, 1, "0 .. 1 (GGX alpha; 0 = smooth)");
        if (auto* n = find(m, "ior")) mat.ior = realIn(*n, child(p, "ior"), 1, 4, "1 .. 4 (index of refraction)");
        if (auto* e = find(m, "emission")) mat.emission = color(*e, child(p, "emission"), 0, FLT_MAX);
        scene.materials.push_back(std::move(mat));
    });
}

std::uint32_t Loader::materialRef(const json& shape, const std::string& p, const Scene& scene) const
{
    const std::string key = child(p, "material");
    const std::string name = string(require(shape, p, "material", "the name of a material"), key);
    const int index = scene.findMaterial(name);
    if (index < 0) {
        std::vector<std::string> names;
        for (const auto& m : scene.materials) names.push_back("\"" + m.name + "\"");
        fail(key, fmt::format("material \"{}\" is not defined: valid {}", name,
                              names.empty() ? std::string("(no materials defined)") : join(names)));
    }
    return std::uint32_t(index);
}

}  // namespace oas::scene::detail
