// "shapes": spheres, quads, triangles, and meshes read from OBJ files.
#include <cfloat>
#include <cmath>

#include <fmt/format.h>

#include "scene/obj.hpp"
#include "scene/scene_loader.hpp"

namespace oas::scene::detail {

namespace fs = std::filesystem;

void Loader::shapes(const json& v, Scene& scene) const
{
    forEachObject(v, "shapes", "shape", [&](const json& s, const std::string& p) {
        const std::string type = choice(require(s, p, "type", "sphere | quad | rectangle | triangle | mesh"), child(p, "type"),
                                        {"sphere", "quad", "rectangle", "triangle", "mesh"});
        if (type == "mesh") {
            mesh(s, p, scene);
            return;
        }
        Shape shape;
        if (type == "sphere") {
            objectKeys(s, p, "a sphere", {"type", "material", "center", "radius", "velocity"});
            shape.type = Shape::Type::Sphere;
            shape.center = vec3(require(s, p, "center", "[x, y, z]"), child(p, "center"));
            shape.radius =
                realIn(require(s, p, "radius", "> 0 (world units)"), child(p, "radius"), 0, FLT_MAX, "> 0 (world units)", true);
        } else if (type == "quad" || type == "rectangle") {
            objectKeys(s, p, "a " + type, {"type", "material", "corner", "edgeU", "edgeV", "velocity"});
            shape.type = Shape::Type::Quad;
            shape.corner = vec3(require(s, p, "corner", "[x, y, z]"), child(p, "corner"));
            shape.edgeU = vec3(require(s, p, "edgeU", "[x, y, z], nonzero"), child(p, "edgeU"));
            shape.edgeV = vec3(require(s, p, "edgeV", "[x, y, z], nonzero, not parallel to edgeU"), child(p, "edgeV"));
        } else {
            objectKeys(s, p, "a triangle", {"type", "material", "p0", "p1", "p2", "velocity"});
            shape.type = Shape::Type::Triangle;
            shape.p0 = vec3(require(s, p, "p0", "[x, y, z]"), child(p, "p0"));
            shape.p1 = vec3(require(s, p, "p1", "[x, y, z]"), child(p, "p1"));
            shape.p2 = vec3(require(s, p, "p2", "[x, y, z]"), child(p, "p2"));
        }
        shape.material = materialRef(s, p, scene);
        if (auto* vel = find(s, "velocity")) shape.velocity = vec3(*vel, child(p, "velocity"));
        const bool light = scene.materials[shape.material].emits();
        const std::string kind = light ? "area light" : "shape";
        if (shape.type == Shape::Type::Quad && isDegenerateParallelogram(shape.edgeU, shape.edgeV))
            fail(child(p, "edgeV"), fmt::format("zero-area {}: edgeU {} and edgeV {} are zero or parallel (area {}): valid "
                                                "non-parallel nonzero edges, area > 0",
                                                kind, show(shape.edgeU), show(shape.edgeV), shape.area()));
        if (shape.type == Shape::Type::Triangle && isDegenerateTriangle(shape.p0, shape.p1, shape.p2))
            fail(p, fmt::format("zero-area {}: triangle p0 {} p1 {} p2 {} (area {}): valid non-collinear points, "
                                "area > 0",
                                kind, show(shape.p0), show(shape.p1), show(shape.p2), shape.area()));
        if (!std::isfinite(shape.area()))
            fail(p, fmt::format("the {}'s area {} overflows 32-bit floats: valid a smaller shape", kind, shape.area()));
        checkFiniteBounds(shape, scene, p, kind);
        scene.shapes.push_back(std::move(shape));
    });
    if (v.empty()) fail("shapes", "[] is empty: valid at least one shape");
}

void Loader::checkFiniteBounds(const Shape& shape, const Scene& scene, const std::string& path, std::string_view kind) const
{
    for (const float t : {0.0f, scene.shutterOpen, scene.shutterClose}) {
        const Aabb box = shape.boundsAt(t);
        const bool finite = std::isfinite(box.lo.x) && std::isfinite(box.lo.y) && std::isfinite(box.lo.z) &&
                            std::isfinite(box.hi.x) && std::isfinite(box.hi.y) && std::isfinite(box.hi.z);
        if (!finite)
            fail(path, fmt::format("the {} moved by velocity {} to time {} leaves the 32-bit float range: valid a "
                                   "smaller velocity or shutter interval",
                                   kind, show(shape.velocity), t));
    }
}

void Loader::mesh(const json& s, const std::string& p, Scene& scene) const
{
    objectKeys(s, p, "a mesh", {"type", "material", "file", "translate", "scale", "velocity"});
    MeshInfo info;
    info.file = string(require(s, p, "file", "an OBJ file path (relative to the scene file)"), child(p, "file"));
    if (info.file.empty()) fail(child(p, "file"), "\"\" is not valid: valid an OBJ file path");
    const std::uint32_t material = materialRef(s, p, scene);
    glm::vec3 translate(0), scale(1), velocity(0);
    if (auto* t = find(s, "translate")) translate = vec3(*t, child(p, "translate"));
    if (auto* sc = find(s, "scale")) {
        const std::string sp = child(p, "scale");
        if (sc->is_number())
            scale = glm::vec3(real(*sc, sp));
        else if (sc->is_array())
            scale = vec3(*sc, sp);
        else
            typeError(*sc, sp, "a number or [sx, sy, sz]", "nonzero finite factors");
        if (scale.x == 0 || scale.y == 0 || scale.z == 0)
            fail(sp, fmt::format("{} has a zero factor: valid nonzero factors (negative mirrors)", show(*sc)));
    }
    if (auto* vel = find(s, "velocity")) velocity = vec3(*vel, child(p, "velocity"));

    const fs::path given(info.file);
    info.resolved = given.is_absolute() ? given : baseDir_ / given;
    ObjMesh obj;
    try {
        obj = readObj(info.resolved);
    } catch (const ObjError& e) {
        fail(child(p, "file"), e.line()
                                   ? fmt::format("cannot load mesh \"{}\": {}", info.file, e.what())
                                   : fmt::format("cannot load mesh \"{}\": {}: valid a readable OBJ file (relative paths start "
                                                 "at the scene file's directory)",
                                                 info.file, e.what()));
    }
    info.firstShape = scene.shapes.size();
    info.degenerateDropped = obj.degenerateDropped;
    for (const auto& tri : obj.triangles) {
        Shape shape;
        shape.type = Shape::Type::Triangle;
        shape.material = material;
        shape.p0 = obj.positions[tri[0]] * scale + translate;
        shape.p1 = obj.positions[tri[1]] * scale + translate;
        shape.p2 = obj.positions[tri[2]] * scale + translate;
        const auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
        if (!finite(shape.p0) || !finite(shape.p1) || !finite(shape.p2))
            fail(child(p, "scale"), fmt::format("mesh \"{}\" scaled by {} and translated by {} leaves the 32-bit "
                                                "float range: valid a smaller scale or translation",
                                                info.file, show(scale), show(translate)));
        if (isDegenerateTriangle(shape.p0, shape.p1, shape.p2)) {
            ++info.degenerateDropped;
            continue;
        }
        if (!std::isfinite(shape.area()))
            fail(child(p, "scale"), fmt::format("mesh \"{}\" scaled by {} has a triangle whose area {} overflows 32-bit "
                                                "floats: valid a smaller scale",
                                                info.file, show(scale), shape.area()));
        shape.velocity = velocity;
        checkFiniteBounds(shape, scene, child(p, "velocity"), "mesh triangle");
        shape.sourceMesh = info.file;
        scene.shapes.push_back(std::move(shape));
    }
    info.triangles = scene.shapes.size() - info.firstShape;
    if (info.triangles == 0)
        fail(child(p, "file"), fmt::format("mesh \"{}\" has no triangles of nonzero area ({} faces, {} zero-area "
                                           "triangles dropped): valid a mesh with at least one triangle",
                                           info.file, obj.faces, info.degenerateDropped));
    scene.meshes.push_back(std::move(info));
}

}  // namespace oas::scene::detail
