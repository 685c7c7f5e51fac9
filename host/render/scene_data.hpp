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

/// Flattens the scene; the BVH bounds cover each shape's motion over the shutter interval.
SceneData flattenScene(const scene::Scene& scene);

}  // namespace oas::render
