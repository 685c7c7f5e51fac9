#pragma once
// A scene flattened for the path tracer: shapes in BVH leaf order, materials, lights (delta
// lights and every emitting shape), BVH nodes and camera constants.
#include <vector>

#include "render/pt_types.hpp"
#include "scene/scene.hpp"

namespace oas::render {

struct SceneData {
    std::vector<pt::PtShape> shapes;
    std::vector<pt::PtMaterial> materials;
    std::vector<pt::PtLight> lights;
    std::vector<pt::PtNode> nodes;
    pt::PtGlobals globals{};
};

/// What the flattened scene contains, for the GPU kernel's specialization (PT_SCENE_FEATURES in
/// shaders/pt/pt_trace.glsl, read by pt_intersect.glsl, pt_bsdf.glsl and pt_light.glsl): code for
/// what is absent compiles away.
struct SceneFeatures {
    bool spheres = false, quads = false, triangles = false;
    bool conductors = false;    ///< conductor materials (smooth or GGX)
    bool pointLights = false;   ///< point or spot lights (area lights are emissive shapes)
    bool movingShapes = false;  ///< shapes with a velocity (a shutter alone moves nothing but the camera's time)
};
SceneFeatures sceneFeatures(const SceneData& data);

/// Flattens the scene; the BVH bounds cover each shape's motion over the shutter interval.
SceneData flattenScene(const scene::Scene& scene);

}  // namespace oas::render
