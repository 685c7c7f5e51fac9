#include "render/scene_data.hpp"

#include <cmath>
#include <cstring>

#include "scene/bvh.hpp"

namespace oas::render {
namespace {

using glm::vec3;
using glm::vec4;

float bitsAsFloat(std::uint32_t bits)
{
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

pt::PtShape toPt(const scene::Shape& s)
{
    pt::PtShape p{};
    float type = pt::PT_SHAPE_SPHERE;
    switch (s.type) {
    case scene::Shape::Type::Sphere:
        p.a = vec4(s.center, s.radius);
        break;
    case scene::Shape::Type::Quad: {
        type = pt::PT_SHAPE_QUAD;
        const vec3 n = glm::cross(s.edgeU, s.edgeV), m = n / glm::dot(n, n);
        p.a = vec4(s.corner, m.x);
        p.b = vec4(s.edgeU, m.y);
        p.c = vec4(s.edgeV, m.z);
        break;
    }
    case scene::Shape::Type::Triangle:
        type = pt::PT_SHAPE_TRIANGLE;
        p.a = vec4(s.p0, 0);
        p.b = vec4(s.p1, 0);
        p.c = vec4(s.p2, 0);
        break;
    }
    p.d = vec4(s.velocity, 0);
    p.e = vec4(type, float(s.material), s.area(), 0);
    return p;
}

}  // namespace

SceneData flattenScene(const scene::Scene& sc)
{
    SceneData data;
    std::vector<scene::Aabb> bounds;
    bounds.reserve(sc.shapes.size());
    for (const auto& s : sc.shapes) {
        scene::Aabb box = s.boundsAt(sc.shutterOpen);
        if (s.moves()) box.extend(s.boundsAt(sc.shutterClose));
        // Pad so that flat shapes (quads in a coordinate plane) keep a box rays can enter.
        const vec3 pad = vec3(1e-4f) * (vec3(1.0f) + glm::abs(box.lo) + glm::abs(box.hi));
        box.lo -= pad;
        box.hi += pad;
        bounds.push_back(box);
    }
    if (!sc.shapes.empty()) {
        const scene::Bvh bvh = scene::buildBvh(bounds, 4);
        for (std::uint32_t index : bvh.order) data.shapes.push_back(toPt(sc.shapes[index]));
        for (const auto& n : bvh.nodes)
            data.nodes.push_back({vec4(n.lo[0], n.lo[1], n.lo[2], bitsAsFloat(n.leftOrFirst)),
                                  vec4(n.hi[0], n.hi[1], n.hi[2], bitsAsFloat(n.count))});
    }
    for (const auto& m : sc.materials) {
        const float type = m.type == scene::Material::Type::Diffuse     ? pt::PT_MAT_DIFFUSE
                           : m.type == scene::Material::Type::Conductor ? pt::PT_MAT_CONDUCTOR
                                                                        : pt::PT_MAT_DIELECTRIC;
        data.materials.push_back({vec4(m.albedo, type), vec4(m.emission, m.roughness), vec4(m.ior, 0, 0, 0)});
    }
    if (data.materials.empty()) data.materials.push_back({});  // keep every buffer non-empty
    for (const auto& l : sc.lights) {
        const float type = l.type == scene::Light::Type::Point ? pt::PT_LIGHT_POINT : pt::PT_LIGHT_SPOT;
        data.lights.push_back(
            {vec4(l.position, type), vec4(l.intensity, 0), vec4(l.direction, l.cosOuter), vec4(l.cosInner, 0, 0, 0)});
    }
    for (std::size_t i = 0; i < data.shapes.size(); ++i) {
        const auto& m = sc.materials[std::size_t(data.shapes[i].e.y)];
        if (m.emits()) data.lights.push_back({vec4(0, 0, 0, pt::PT_LIGHT_AREA), vec4(0, 0, 0, float(i)), vec4(0), vec4(0)});
    }
    const float lightCount = float(data.lights.size());
    if (data.lights.empty()) data.lights.push_back({});
    if (data.shapes.empty()) data.shapes.push_back({});
    if (data.nodes.empty()) data.nodes.push_back({});

    const auto& cam = sc.camera;
    const vec3 forward = glm::normalize(cam.lookAt - cam.position);
    const vec3 right = glm::normalize(glm::cross(forward, cam.up));
    const vec3 up = glm::cross(right, forward);
    const float tanY = std::tan(glm::radians(cam.fovYDegrees) * 0.5f);
    const float aspect = float(sc.width) / float(sc.height);
    auto& g = data.globals;
    g.cameraPosition = vec4(cam.position, cam.apertureRadius);
    g.cameraRight = vec4(right, tanY * aspect);
    g.cameraUp = vec4(up, tanY);
    g.cameraForward = vec4(forward, cam.focusDistance);
    g.time = vec4(sc.shutterOpen, sc.shutterClose, lightCount, float(sc.shapes.empty() ? 0 : data.nodes.size()));
    g.environment = vec4(sc.environment, float(sc.width));
    g.image = vec4(float(sc.width), float(sc.height), 0, 0);
    return data;
}

SceneFeatures sceneFeatures(const SceneData& data)
{
    SceneFeatures f;
    for (const auto& shape : data.shapes) {
        f.spheres |= shape.e.x == pt::PT_SHAPE_SPHERE;
        f.quads |= shape.e.x == pt::PT_SHAPE_QUAD;
        f.triangles |= shape.e.x == pt::PT_SHAPE_TRIANGLE;
        f.movingShapes |= shape.d.x != 0.0f || shape.d.y != 0.0f || shape.d.z != 0.0f;
    }
    for (const auto& material : data.materials) f.conductors |= material.albedo.w == pt::PT_MAT_CONDUCTOR;
    for (const auto& light : data.lights) f.pointLights |= light.position.w != pt::PT_LIGHT_AREA;
    return f;
}

}  // namespace oas::render
