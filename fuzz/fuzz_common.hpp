#pragma once
// Shared by the libFuzzer targets: invariant checks that turn a silent wrong result into a crash
// libFuzzer can report, and the BVH checks both targets run (docs/FUZZING.md).
//
// A failed check prints "oas-fuzz: invariant <category> violated: <detail>" and aborts. Categories
// listed in the environment variable OAS_FUZZ_IGNORE (comma-separated, e.g.
// OAS_FUZZ_IGNORE=camera-nonfinite,motion-overflow) are not checked, so a long run can go on past
// a known finding. OAS_FUZZ_VERBOSE=1 prints every expected error and every accepted input.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

#include <cxxabi.h>

#include "scene/bvh.hpp"

namespace oas::fuzz {

inline bool ignored(const char* category)
{
    static const std::string list = [] {
        const char* env = std::getenv("OAS_FUZZ_IGNORE");
        return "," + std::string(env ? env : "") + ",";
    }();
    return list.find("," + std::string(category) + ",") != std::string::npos;
}

/// OAS_FUZZ_VERBOSE=1: print each expected error (for looking at what a corpus exercises).
inline bool verbose()
{
    static const bool on = [] {
        const char* env = std::getenv("OAS_FUZZ_VERBOSE");
        return env && *env && *env != '0';
    }();
    return on;
}

[[noreturn]] inline void violated(const char* category, const std::string& detail)
{
    std::fprintf(stderr, "oas-fuzz: invariant %s violated: %s\n", category, detail.c_str());
    std::fflush(stderr);
    std::abort();
}

#define OAS_FUZZ_CHECK(category, cond, detail)                                                                                   \
    do {                                                                                                                         \
        if (!(cond) && !::oas::fuzz::ignored(category)) ::oas::fuzz::violated(category, std::string(#cond) + ": " + (detail));   \
    } while (0)

/// Inside a catch (...): report the exception that escaped (type and what()) and abort.
[[noreturn]] inline void unexpectedException(const char* api)
{
    std::string type = "(unknown type)", what;
    if (const std::type_info* t = abi::__cxa_current_exception_type()) {
        int status = 0;
        char* name = abi::__cxa_demangle(t->name(), nullptr, nullptr, &status);
        type = status == 0 && name ? name : t->name();
        std::free(name);
    }
    try {
        throw;
    } catch (const std::exception& e) {
        what = e.what();
    } catch (...) {
    }
    if (what.size() > 400) what = what.substr(0, 400) + "...";
    violated("unexpected-exception", std::string(api) + " threw " + type + ": " + what);
}

inline std::string str(const glm::vec3& v)
{
    char buf[128];
    std::snprintf(buf, sizeof buf, "[%g, %g, %g]", double(v.x), double(v.y), double(v.z));
    return buf;
}

inline bool finite(const glm::vec3& v)
{
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The structural guarantees of host/scene/bvh.hpp for a tree built from `boxes` with
/// `maxLeafSize`, then traversals of `rays` (origin, direction) compared with brute force:
/// every primitive whose (valid, finite) box a ray enters must be visited.
inline void checkBvh(const scene::Bvh& bvh, const std::vector<scene::Aabb>& boxes, std::uint32_t maxLeafSize,
                     const std::vector<std::pair<glm::vec3, glm::vec3>>& rays)
{
    using scene::Aabb;
    using scene::BvhNode;
    const std::size_t n = boxes.size();
    OAS_FUZZ_CHECK("bvh-structure", !bvh.nodes.empty(), "no nodes");
    OAS_FUZZ_CHECK("bvh-structure", bvh.order.size() == n,
                   std::to_string(bvh.order.size()) + " order entries for " + std::to_string(n) + " primitives");
    std::vector<std::uint8_t> seen(n, 0);
    for (std::uint32_t p : bvh.order) {
        OAS_FUZZ_CHECK("bvh-structure", p < n, "order holds " + std::to_string(p));
        OAS_FUZZ_CHECK("bvh-structure", !seen[p], "primitive " + std::to_string(p) + " twice in order");
        seen[p] = 1;
    }
    if (n == 0) {
        OAS_FUZZ_CHECK("bvh-structure", bvh.nodes.size() == 1 && bvh.nodes[0].count == 0 && bvh.nodes[0].bounds().empty(),
                       "the empty tree is not one empty leaf");
        return;
    }
    // Walk the tree: each node reached once, depth < kBvhMaxDepth, leaves cover order exactly.
    std::vector<std::uint8_t> visited(bvh.nodes.size(), 0);
    std::vector<std::uint32_t> leafCover(n, 0);
    struct Item {
        std::uint32_t node, depth;
    };
    std::vector<Item> stack{{0, 0}};
    std::size_t reached = 0;
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        OAS_FUZZ_CHECK("bvh-structure", it.node < bvh.nodes.size(), "child index " + std::to_string(it.node));
        OAS_FUZZ_CHECK("bvh-structure", !visited[it.node], "node " + std::to_string(it.node) + " reached twice");
        visited[it.node] = 1;
        ++reached;
        OAS_FUZZ_CHECK("bvh-depth", it.depth < scene::kBvhMaxDepth,
                       "node at depth " + std::to_string(it.depth) + " with " + std::to_string(n) + " primitives");
        const BvhNode& nd = bvh.nodes[it.node];
        const Aabb box = nd.bounds();
        if (nd.isLeaf()) {
            OAS_FUZZ_CHECK("bvh-structure", nd.count <= std::max<std::uint32_t>(maxLeafSize, 1),
                           "leaf of " + std::to_string(nd.count) + " primitives");
            OAS_FUZZ_CHECK("bvh-structure", std::uint64_t(nd.leftOrFirst) + nd.count <= n, "leaf range past order");
            for (std::uint32_t i = nd.leftOrFirst; i < nd.leftOrFirst + nd.count; ++i) {
                ++leafCover[i];
                const Aabb& pb = boxes[bvh.order[i]];
                if (pb.valid())
                    OAS_FUZZ_CHECK("bvh-bounds", box.contains(pb),
                                   "leaf box " + str(box.lo) + ".." + str(box.hi) + " misses primitive box " + str(pb.lo) + ".." +
                                       str(pb.hi));
            }
        } else {
            OAS_FUZZ_CHECK("bvh-structure", std::uint64_t(nd.leftOrFirst) + 1 < bvh.nodes.size(),
                           "interior node " + std::to_string(it.node) + " with children past the node array");
            OAS_FUZZ_CHECK("bvh-structure", nd.leftOrFirst > it.node, "child index not after its parent");
            for (std::uint32_t c : {nd.leftOrFirst, nd.leftOrFirst + 1}) {
                const Aabb cb = bvh.nodes[c].bounds();
                if (cb.valid()) OAS_FUZZ_CHECK("bvh-bounds", box.contains(cb), "interior box does not contain its child's box");
                stack.push_back({c, it.depth + 1});
            }
        }
    }
    OAS_FUZZ_CHECK("bvh-structure", reached == bvh.nodes.size(),
                   std::to_string(bvh.nodes.size() - reached) + " nodes unreachable from the root");
    for (std::size_t i = 0; i < n; ++i)
        OAS_FUZZ_CHECK("bvh-structure", leafCover[i] == 1,
                       "order[" + std::to_string(i) + "] in " + std::to_string(leafCover[i]) + " leaves");
    OAS_FUZZ_CHECK("bvh-structure", scene::bvhDepth(bvh) <= scene::kBvhMaxDepth, "bvhDepth too large");
    (void)scene::bvhSahCost(bvh);

    // Traversal against brute force (tMax never shrinks, so every entered leaf is visited).
    if (n > 4096) return;
    for (const auto& [origin, dir] : rays) {
        if (!finite(origin) || !finite(dir)) continue;
        const float tMax = std::numeric_limits<float>::infinity();
        std::vector<std::uint8_t> hit(n, 0);
        scene::traverse(bvh, origin, dir, tMax, [&](std::uint32_t prim, float&) {
            OAS_FUZZ_CHECK("bvh-structure", prim < n, "traverse visited primitive " + std::to_string(prim));
            hit[prim] = 1;
        });
        const glm::vec3 inv = scene::safeInverse(dir);
        for (std::size_t p = 0; p < n; ++p) {
            const Aabb& b = boxes[p];
            if (!b.valid() || !finite(b.lo) || !finite(b.hi)) continue;
            BvhNode leaf{};
            for (int a = 0; a < 3; ++a) {
                leaf.lo[a] = b.lo[a];
                leaf.hi[a] = b.hi[a];
            }
            float tEntry;
            if (scene::intersectNode(leaf, origin, inv, 0.f, tMax, tEntry))
                OAS_FUZZ_CHECK("bvh-traversal", hit[p],
                               "ray " + str(origin) + " dir " + str(dir) + " enters the box of primitive " + std::to_string(p) +
                                   " " + str(b.lo) + ".." + str(b.hi) + " but traverse() never visits it");
        }
    }
}

}  // namespace oas::fuzz
