// libFuzzer target: oas::scene::parseObj on arbitrary bytes (docs/FUZZING.md).
//
// Expected: an ObjMesh, or oas::scene::ObjError naming "fuzz.obj:<line>". Findings: any other
// exception, a crash, a sanitizer report, a hang, or a mesh that breaks obj.hpp's promises
// (indices in range, finite positions, no zero-area triangle kept), then the BVH over the mesh's
// triangles (as the renderer builds it for an expanded mesh) checked as in fuzz_scene.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_common.hpp"
#include "scene/bvh.hpp"
#include "scene/obj.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace oas::scene;
    using oas::fuzz::finite;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    ObjMesh mesh;
    try {
        mesh = parseObj(text, "fuzz.obj");
    } catch (const ObjError& e) {
        if (oas::fuzz::verbose()) std::fprintf(stderr, "ObjError: %s\n", e.what());
        OAS_FUZZ_CHECK("error-message", std::string_view(e.what()).substr(0, 9) == "fuzz.obj:" && e.line() > 0,
                       std::string("message does not name fuzz.obj:<line>: ") + e.what());
        return 0;
    } catch (...) {
        oas::fuzz::unexpectedException("parseObj");
    }
    try {
        OAS_FUZZ_CHECK("obj-range", mesh.triangles.size() + mesh.degenerateDropped >= mesh.faces, "fewer triangles than faces");
        for (const auto& p : mesh.positions) OAS_FUZZ_CHECK("obj-range", finite(p), oas::fuzz::str(p));
        std::vector<Aabb> boxes;
        boxes.reserve(mesh.triangles.size());
        for (const auto& t : mesh.triangles) {
            for (std::uint32_t i : t)
                OAS_FUZZ_CHECK("obj-range", i < mesh.positions.size(),
                               "index " + std::to_string(i) + " of " + std::to_string(mesh.positions.size()));
            const auto &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
            OAS_FUZZ_CHECK("obj-range", !isDegenerateTriangle(a, b, c), "a zero-area triangle was kept");
            Aabb box;
            box.extend(a);
            box.extend(b);
            box.extend(c);
            boxes.push_back(box);
        }
        const Bvh bvh = buildBvh(boxes, 4);
        std::vector<std::pair<glm::vec3, glm::vec3>> rays = {
            {{0, 0, 5}, {0, 0, -1}}, {{0, 0, 0}, {1, 0, 0}}, {{-3, 2, 1}, {1, -0.5f, -0.2f}}};
        if (!mesh.positions.empty()) rays.push_back({mesh.positions.front(), {0, 1, 0}});
        oas::fuzz::checkBvh(bvh, boxes, 4, rays);
        if (oas::fuzz::verbose())
            std::fprintf(stderr, "loaded: %zu positions, %zu faces, %zu triangles, %zu dropped\n", mesh.positions.size(),
                         mesh.faces, mesh.triangles.size(), mesh.degenerateDropped);
    } catch (...) {
        oas::fuzz::unexpectedException("buildBvh");
    }
    return 0;
}
