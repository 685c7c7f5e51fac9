#pragma once
// Bounding volume hierarchy over axis-aligned primitive bounds, built on the host with the binned
// surface area heuristic and traversed both here (CPU reference tracer, tests) and in a GLSL
// compute shader. The node array is flat and std430-friendly: upload `nodes` and `order` as two
// storage buffers as they are.
//
// Tree shape:
//   - nodes[0] is the root. The tree of 0 primitives is a single leaf with count 0 and an empty
//     box (lo = +inf, hi = -inf), which no ray enters.
//   - An interior node (count == 0) has its children at leftOrFirst and leftOrFirst + 1.
//   - A leaf (count > 0) covers order[leftOrFirst .. leftOrFirst + count); order holds primitive
//     indices (into the input vector) so that every leaf's primitives are contiguous.
//   - Every primitive index appears exactly once in `order`; every leaf has 1..maxLeafSize
//     primitives (unless the tree is empty); a node's box is the union of its primitives' boxes.
//   - Depth (edges from the root) is below kBvhMaxDepth, so a traversal stack of kBvhMaxDepth
//     entries never overflows (one push per level descended).
//
// GLSL mirror of BvhNode (std430, 32 bytes, 16-byte aligned):
//   struct BvhNode { vec4 loFirst; vec4 hiCount; };
//   lo = loFirst.xyz, leftOrFirst = floatBitsToUint(loFirst.w),
//   hi = hiCount.xyz, count = floatBitsToUint(hiCount.w).
// Robust slab test (as traverse() below does it): invDir = dir == 0 ? +inf : 1 / dir per axis
// (treat -0 as +0), take the near plane from lo where invDir >= 0 else hi, and combine with
// comparisons that ignore NaN (0 * inf on a plane the ray lies in): tNear = t > tNear ? t : tNear,
// tFar = t < tFar ? t : tFar. Hit when tNear <= tFar.
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace oas::scene {

/// Axis-aligned box. The default box is empty (lo = +inf, hi = -inf): extending it by anything
/// gives that thing, and it has zero surface area. Flat or point boxes (lo == hi on some axes) are
/// valid and non-empty.
struct Aabb {
    glm::vec3 lo{std::numeric_limits<float>::infinity()};
    glm::vec3 hi{-std::numeric_limits<float>::infinity()};

    void extend(const glm::vec3& p)
    {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Aabb& b)
    {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    /// True when lo <= hi on every axis (false for the default box and for NaN coordinates).
    bool valid() const { return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z; }
    bool empty() const { return !valid(); }
    /// hi - lo, clamped to 0 on axes where the box is empty.
    glm::vec3 extent() const
    {
        glm::vec3 d = hi - lo;
        // (0 < d) ? d : 0 also maps NaN and -inf to 0.
        return {0.f < d.x ? d.x : 0.f, 0.f < d.y ? d.y : 0.f, 0.f < d.z ? d.z : 0.f};
    }
    glm::vec3 center() const { return 0.5f * (lo + hi); }
    /// 2 (xy + yz + zx); 0 for empty, flat-in-two-axes and point boxes.
    float surfaceArea() const
    {
        glm::vec3 d = extent();
        return 2.f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    /// Index of the longest axis (0 = x on ties).
    int largestAxis() const
    {
        glm::vec3 d = extent();
        return d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    }
    /// Closed containment: every point of b lies in this box. An empty b is contained in anything.
    bool contains(const Aabb& b) const
    {
        if (b.empty()) return true;
        return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && b.hi.x <= hi.x && b.hi.y <= hi.y && b.hi.z <= hi.z;
    }
    bool contains(const glm::vec3& p) const
    {
        return lo.x <= p.x && lo.y <= p.y && lo.z <= p.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
    }
};

/// 32 bytes, std430-compatible as two vec4s (see the GLSL mirror above).
struct BvhNode {
    float lo[3];
    std::uint32_t leftOrFirst;  // interior: left child (right = left + 1); leaf: first in `order`
    float hi[3];
    std::uint32_t count;  // 0 = interior node; > 0 = leaf with `count` primitives

    bool isLeaf() const { return count != 0; }
    Aabb bounds() const { return Aabb{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
};
static_assert(sizeof(BvhNode) == 32);
static_assert(std::is_standard_layout_v<BvhNode> && std::is_trivially_copyable_v<BvhNode>);
static_assert(offsetof(BvhNode, leftOrFirst) == 12 && offsetof(BvhNode, hi) == 16 && offsetof(BvhNode, count) == 28);

/// Upper bound on node depth + 1: every node is at depth < kBvhMaxDepth (root depth 0), so a
/// traversal stack of kBvhMaxDepth entries is always enough.
inline constexpr std::uint32_t kBvhMaxDepth = 64;

struct Bvh {
    std::vector<BvhNode> nodes;        // nodes[0] is the root
    std::vector<std::uint32_t> order;  // primitive indices in leaf order
};

/// Builds the tree top-down with the binned SAH (16 bins per axis over the centroid bounds, all
/// three axes; traversal cost 1, intersection cost 1 per primitive). A node becomes a leaf when it
/// holds at most one primitive, or at most maxLeafSize primitives and no split is cheaper than the
/// leaf. maxLeafSize is a hard cap (0 counts as 1): larger nodes are always split, by the best SAH
/// plane, or by the object median along the widest centroid axis where no plane separates them
/// (all centroids equal, e.g. identical boxes) or the depth limit nears.
///
/// Input boxes should have finite coordinates. Flat and point boxes are fine; empty boxes (the
/// default Aabb) are allowed and placed in some leaf but add nothing to the node bounds, so no ray
/// reaches them through those bounds.
Bvh buildBvh(const std::vector<Aabb>& primitiveBounds, std::uint32_t maxLeafSize = 4);

/// Number of levels (1 for a root-only tree, 0 for no nodes).
std::uint32_t bvhDepth(const Bvh& bvh);

/// SAH cost of the tree with the builder's constants, relative to the root area:
/// sum over interior nodes of A(n)/A(root) * 1 + sum over leaves of A(n)/A(root) * count.
/// For comparing builds; 0 for an empty tree, the primitive count where the root's area is 0.
double bvhSahCost(const Bvh& bvh);

/// Slab test of a ray (origin, invDir computed as in traverse()) against a node's box over
/// [tMin, tMax]. On a hit returns true and sets tEntry to the entry distance (>= tMin).
inline bool intersectNode(const BvhNode& node, const glm::vec3& origin, const glm::vec3& invDir, float tMin, float tMax,
                          float& tEntry)
{
    float tNear = tMin, tFar = tMax;
    for (int a = 0; a < 3; ++a) {
        const bool positive = invDir[a] >= 0.f;
        const float nearPlane = positive ? node.lo[a] : node.hi[a];
        const float farPlane = positive ? node.hi[a] : node.lo[a];
        const float t0 = (nearPlane - origin[a]) * invDir[a];
        const float t1 = (farPlane - origin[a]) * invDir[a];
        // NaN (0 * inf: the ray runs inside the slab's boundary plane) leaves the interval alone.
        tNear = t0 > tNear ? t0 : tNear;
        tFar = t1 < tFar ? t1 : tFar;
    }
    tEntry = tNear;
    return tNear <= tFar;
}

/// Per-axis 1 / dir with zero components (either sign) mapped to +inf.
inline glm::vec3 safeInverse(const glm::vec3& dir)
{
    const float inf = std::numeric_limits<float>::infinity();
    return {dir.x == 0.f ? inf : 1.f / dir.x, dir.y == 0.f ? inf : 1.f / dir.y, dir.z == 0.f ? inf : 1.f / dir.z};
}

/// Visits candidate primitives for the ray origin + t dir, t in [0, tMax]: calls
/// fn(primIndex, tMaxInOut) for each primitive of each leaf whose box the ray enters before the
/// current tMax, nearer child first. fn may lower tMaxInOut (closest hit) to prune the rest. If fn
/// returns bool, returning false stops the traversal (any-hit queries). dir need not be
/// normalised; zero components are fine. bvh must come from buildBvh (depth < kBvhMaxDepth).
template <class HitFn>
void traverse(const Bvh& bvh, const glm::vec3& origin, const glm::vec3& dir, float tMax, HitFn&& fn)
{
    if (bvh.nodes.empty()) return;
    const glm::vec3 invDir = safeInverse(dir);
    struct Entry {
        std::uint32_t node;
        float tEntry;
    };
    Entry stack[kBvhMaxDepth];
    std::uint32_t size = 0;
    float tEntry;
    if (!intersectNode(bvh.nodes[0], origin, invDir, 0.f, tMax, tEntry)) return;
    std::uint32_t current = 0;
    for (;;) {
        const BvhNode& node = bvh.nodes[current];
        if (node.isLeaf()) {
            for (std::uint32_t i = node.leftOrFirst, end = node.leftOrFirst + node.count; i < end; ++i) {
                if constexpr (std::is_same_v<std::invoke_result_t<HitFn&, std::uint32_t, float&>, bool>) {
                    if (!fn(bvh.order[i], tMax)) return;
                } else {
                    fn(bvh.order[i], tMax);
                }
            }
        } else {
            const std::uint32_t left = node.leftOrFirst, right = left + 1;
            float tLeft, tRight;
            const bool hitLeft = intersectNode(bvh.nodes[left], origin, invDir, 0.f, tMax, tLeft);
            const bool hitRight = intersectNode(bvh.nodes[right], origin, invDir, 0.f, tMax, tRight);
            if (hitLeft && hitRight) {
                const bool leftFirst = tLeft <= tRight;
                assert(size < kBvhMaxDepth);  // buildBvh guarantees depth < kBvhMaxDepth
                stack[size++] = leftFirst ? Entry{right, tRight} : Entry{left, tLeft};
                current = leftFirst ? left : right;
                continue;
            }
            if (hitLeft || hitRight) {
                current = hitLeft ? left : right;
                continue;
            }
        }
        // Pop the next subtree that the ray still reaches before the (possibly shrunk) tMax.
        for (;;) {
            if (size == 0) return;
            const Entry e = stack[--size];
            if (e.tEntry <= tMax) {
                current = e.node;
                break;
            }
        }
    }
}

}  // namespace oas::scene
