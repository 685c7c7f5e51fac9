// libFuzzer target: oas::scene::parseScene on arbitrary bytes (docs/FUZZING.md).
//
// Expected: a Scene, or oas::scene::SceneError. Findings: any other exception, a crash, a
// sanitizer report, a hang, or a loaded scene that breaks the loader's promises ("everything is
// validated at load time", scene.hpp): indices in range, finite values, positive areas, a usable
// camera basis. A loaded scene then goes through what a render does with it before the GPU, as far
// as host/scene provides it: summary(), the primitive bounds as host/render/scene_data.cpp computes
// them (over the shutter interval, padded), buildBvh with the renderer's leaf size, the BVH
// invariants and traversals compared with brute force.
//
// Mesh paths resolve against $OAS_FUZZ_MESH_DIR, by default the repository's scenes/ directory
// (so "meshes/cube.obj" loads); the target only reads files, never writes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "fuzz_common.hpp"
#include "scene/bvh.hpp"
#include "scene/scene.hpp"

namespace {

using namespace oas::scene;
using glm::vec3;

const std::filesystem::path& meshDir()
{
    static const std::filesystem::path dir = [] {
        const char* env = std::getenv("OAS_FUZZ_MESH_DIR");
        return std::filesystem::path(env && *env ? env : OAS_FUZZ_DEFAULT_MESH_DIR);
    }();
    return dir;
}

// As host/render/scene_data.cpp (flattenScene, on Shape::boundsAt): kept in step by hand.
Aabb rendererBounds(const Scene& sc, const Shape& s)
{
    Aabb box = s.boundsAt(sc.shutterOpen);
    if (s.moves()) box.extend(s.boundsAt(sc.shutterClose));
    const vec3 pad = vec3(1e-4f) * (vec3(1.0f) + glm::abs(box.lo) + glm::abs(box.hi));
    box.lo -= pad;
    box.hi += pad;
    return box;
}

void checkScene(const Scene& sc)
{
    using oas::fuzz::finite;
    using oas::fuzz::str;
    OAS_FUZZ_CHECK("scene-range", sc.width >= 1 && sc.width <= 16384 && sc.height >= 1 && sc.height <= 16384,
                   std::to_string(sc.width) + "x" + std::to_string(sc.height));
    OAS_FUZZ_CHECK("scene-range", !sc.shapes.empty(), "no shapes");
    OAS_FUZZ_CHECK("scene-range",
                   std::isfinite(sc.shutterOpen) && std::isfinite(sc.shutterClose) && sc.shutterOpen <= sc.shutterClose,
                   "shutter");
    OAS_FUZZ_CHECK("scene-range", finite(sc.environment), str(sc.environment));

    // Camera: finite, and the basis the renderer builds from it (scene_data.cpp) is finite.
    const Camera& cam = sc.camera;
    OAS_FUZZ_CHECK("scene-range", finite(cam.position) && finite(cam.lookAt) && finite(cam.up), "camera vectors");
    OAS_FUZZ_CHECK("scene-range", cam.fovYDegrees > 0 && cam.fovYDegrees < 180, std::to_string(cam.fovYDegrees));
    OAS_FUZZ_CHECK("scene-range", cam.apertureRadius >= 0 && std::isfinite(cam.apertureRadius), "aperture");
    OAS_FUZZ_CHECK("camera-nonfinite", std::isfinite(cam.focusDistance) && cam.focusDistance > 0,
                   "focusDistance " + std::to_string(cam.focusDistance) + " for position " + str(cam.position) + " lookAt " +
                       str(cam.lookAt));
    const vec3 forward = glm::normalize(cam.lookAt - cam.position);
    const vec3 right = glm::normalize(glm::cross(forward, cam.up));
    const vec3 up = glm::cross(right, forward);
    OAS_FUZZ_CHECK("camera-nonfinite", finite(forward) && finite(right) && finite(up),
                   "camera basis forward " + str(forward) + " right " + str(right) + " from position " + str(cam.position) +
                       " lookAt " + str(cam.lookAt) + " up " + str(cam.up));

    OAS_FUZZ_CHECK("scene-range", !sc.materials.empty(), "shapes without materials");
    for (const Material& m : sc.materials) {
        OAS_FUZZ_CHECK("scene-range", !m.name.empty(), "unnamed material");
        OAS_FUZZ_CHECK("scene-range",
                       finite(m.albedo) && finite(m.emission) && std::isfinite(m.roughness) && std::isfinite(m.ior), m.name);
    }
    for (std::size_t i = 0; i < sc.shapes.size(); ++i) {
        const Shape& s = sc.shapes[i];
        OAS_FUZZ_CHECK("scene-range", s.material < sc.materials.size(), "shape material index");
        OAS_FUZZ_CHECK("scene-range",
                       finite(s.center) && std::isfinite(s.radius) && finite(s.corner) && finite(s.edgeU) && finite(s.edgeV) &&
                           finite(s.p0) && finite(s.p1) && finite(s.p2) && finite(s.velocity),
                       "shape " + std::to_string(i));
        const float area = s.area();
        OAS_FUZZ_CHECK("shape-area", std::isfinite(area) && area > 0,
                       "shape " + std::to_string(i) + " area " + std::to_string(area));
        (void)sc.isAreaLight(s);
    }
    for (const Light& l : sc.lights) {
        OAS_FUZZ_CHECK("scene-range", finite(l.position) && finite(l.intensity), "light");
        if (l.type == Light::Type::Spot) {
            OAS_FUZZ_CHECK("light-nonfinite", finite(l.direction) && std::fabs(glm::length(l.direction) - 1) < 1e-3f,
                           "spot direction " + str(l.direction) + " is not a unit vector");
            OAS_FUZZ_CHECK("scene-range", l.cosOuter <= l.cosInner && l.cosOuter >= -1 && l.cosInner <= 1, "spot cosines");
        }
    }
    std::size_t next = 0;
    for (const MeshInfo& m : sc.meshes) {
        OAS_FUZZ_CHECK("scene-range", m.firstShape >= next && m.triangles > 0 && m.firstShape + m.triangles <= sc.shapes.size(),
                       "mesh range " + m.file);
        for (std::size_t i = m.firstShape; i < m.firstShape + m.triangles; ++i)
            OAS_FUZZ_CHECK("scene-range", sc.shapes[i].type == Shape::Type::Triangle && sc.shapes[i].sourceMesh == m.file,
                           "mesh triangle " + std::to_string(i));
        next = m.firstShape + m.triangles;
    }
    OAS_FUZZ_CHECK("scene-range", sc.integrator.maxDepth >= 1 && sc.integrator.maxDepth <= 256, "maxDepth");
    OAS_FUZZ_CHECK("scene-range", sc.integrator.rouletteStartDepth <= sc.integrator.maxDepth, "roulette");
    OAS_FUZZ_CHECK("scene-range", sc.sampler.spp >= 1 && sc.sampler.spp <= (1u << 24), "spp");
    (void)sc.hasMotionBlur();
    (void)sc.hasDepthOfField();
    (void)sc.areaLightCount();
    (void)sc.hasEnvironment();
    (void)summary(sc);

    // What flattenScene does before the GPU: bounds over the shutter, padded, then the BVH.
    std::vector<Aabb> boxes;
    boxes.reserve(sc.shapes.size());
    for (std::size_t i = 0; i < sc.shapes.size(); ++i) {
        const Aabb box = rendererBounds(sc, sc.shapes[i]);
        OAS_FUZZ_CHECK("motion-overflow", box.valid() && finite(box.lo) && finite(box.hi),
                       "shape " + std::to_string(i) + " (velocity " + str(sc.shapes[i].velocity) + ", shutter [" +
                           std::to_string(sc.shutterOpen) + ", " + std::to_string(sc.shutterClose) +
                           "]) gets the render bounds " + str(box.lo) + ".." + str(box.hi));
        boxes.push_back(box);
    }
    const Bvh bvh = buildBvh(boxes, 4);
    std::vector<std::pair<vec3, vec3>> rays = {{cam.position, cam.lookAt - cam.position},
                                               {cam.position, {1, 0, 0}},
                                               {cam.position, {0, -1, 0}},
                                               {cam.position, {0, 0, -1}},
                                               {cam.lookAt, {-0.3f, 0.5f, 0.7f}},
                                               {vec3(0), {1, 1, 1}}};
    oas::fuzz::checkBvh(bvh, boxes, 4, rays);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    Scene scene;
    try {
        scene = parseScene(text, "fuzz.json", meshDir());
    } catch (const SceneError& e) {
        if (oas::fuzz::verbose()) std::fprintf(stderr, "SceneError: %s\n", e.what());
        OAS_FUZZ_CHECK("error-message", std::string(e.what()).rfind("fuzz.json: ", 0) == 0,
                       std::string("message does not start with the file name: ") + e.what());
        return 0;
    } catch (...) {
        oas::fuzz::unexpectedException("parseScene");
    }
    // Strict JSON: a NUL byte is never valid outside a string (and inside one only escaped), so
    // an accepted input holds none (nlohmann's lexer takes a raw NUL for the end of the input).
    const std::size_t nul = text.find('\0');
    OAS_FUZZ_CHECK("nul-accepted", nul == std::string::npos,
                   "accepted a scene with a NUL byte at offset " + std::to_string(nul) + " of " + std::to_string(text.size()) +
                       " (the bytes after it were ignored)");
    try {
        checkScene(scene);
        if (oas::fuzz::verbose()) std::fprintf(stderr, "loaded: %s\n", summary(scene).c_str());
    } catch (...) {
        oas::fuzz::unexpectedException("summary/buildBvh");
    }
    return 0;
}
