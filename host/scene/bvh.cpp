#include "scene/bvh.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace oas::scene {
namespace {

constexpr int kBins = 16;
constexpr float kTraversalCost = 1.f;
constexpr float kIntersectionCost = 1.f;

// Working copy of one primitive, permuted in place while the tree is built; sequential access
// keeps the per-level passes cache friendly even for millions of primitives.
struct PrimRef {
    Aabb box;            // empty for invalid input boxes
    glm::vec3 centroid;  // finite; the origin for empty boxes
    std::uint32_t index;
};

struct Bounds {
    Aabb box;   // union of the primitives' boxes
    Aabb cbox;  // bounds of their centroids
    void add(const PrimRef& r)
    {
        box.extend(r.box);
        cbox.extend(r.centroid);
    }
};

struct Task {
    std::uint32_t node, begin, end, depth;
    Bounds bounds;
};

struct Split {
    int axis = -1;  // -1: none found
    int bin = 0;    // left side = bins [0, bin)
    float cost = 0.f;
};

// Maps a centroid coordinate to its bin. Written so that NaN (from an overflowing scale) and
// out-of-range values land in a valid bin; binning and partitioning share it, so they agree.
inline int binOf(float c, float lo, float scale)
{
    const float k = (c - lo) * scale;
    return k < float(kBins) ? (k > 0.f ? int(k) : 0) : kBins - 1;
}

// Area measure for the SAH. When the parent's surface area is 0 (all boxes lie on one line) the
// sum of the extents still ranks splits sensibly.
inline float measure(const Aabb& b, bool useArea)
{
    if (useArea) return b.surfaceArea();
    const glm::vec3 d = b.extent();
    return d.x + d.y + d.z;
}

Split findSahSplit(const PrimRef* refs, std::uint32_t n, const Bounds& bounds)
{
    struct Bin {
        Aabb box;
        std::uint32_t count = 0;
    };
    Split best;
    const bool useArea = bounds.box.surfaceArea() > 0.f;
    const float parent = measure(bounds.box, useArea);
    if (!(parent > 0.f)) return best;

    std::array<std::array<Bin, kBins>, 3> bins{};
    std::array<float, 3> scale{};
    std::array<bool, 3> active{};
    const glm::vec3 cext = bounds.cbox.extent();
    const glm::vec3 clo = bounds.cbox.lo;
    for (int a = 0; a < 3; ++a) {
        active[a] = cext[a] > 0.f;
        scale[a] = active[a] ? float(kBins) / cext[a] : 0.f;
    }
    if (!active[0] && !active[1] && !active[2]) return best;

    for (std::uint32_t i = 0; i < n; ++i) {
        const PrimRef& r = refs[i];
        for (int a = 0; a < 3; ++a) {
            if (!active[a]) continue;
            Bin& b = bins[a][binOf(r.centroid[a], clo[a], scale[a])];
            b.box.extend(r.box);
            ++b.count;
        }
    }

    for (int a = 0; a < 3; ++a) {
        if (!active[a]) continue;
        // rightCost[s] = measure * count of bins [s, kBins), for split s in 1..kBins-1.
        std::array<float, kBins> rightCost{};
        std::array<std::uint32_t, kBins> rightCount{};
        Aabb acc;
        std::uint32_t count = 0;
        for (int s = kBins - 1; s >= 1; --s) {
            acc.extend(bins[a][s].box);
            count += bins[a][s].count;
            rightCost[s] = measure(acc, useArea) * float(count);
            rightCount[s] = count;
        }
        acc = Aabb{};
        count = 0;
        for (int s = 1; s < kBins; ++s) {
            acc.extend(bins[a][s - 1].box);
            count += bins[a][s - 1].count;
            if (count == 0 || rightCount[s] == 0) continue;
            const float cost =
                kTraversalCost + kIntersectionCost * (measure(acc, useArea) * float(count) + rightCost[s]) / parent;
            if (best.axis < 0 || cost < best.cost) best = Split{a, s, cost};
        }
    }
    return best;
}

// Reorders refs[begin, end) so that the primitives for which goesLeft holds come first, and
// returns the boundary with the bounds of both sides.
template <class Pred>
std::uint32_t partition(std::vector<PrimRef>& refs, std::uint32_t begin, std::uint32_t end, Pred goesLeft, Bounds& left,
                        Bounds& right)
{
    std::uint32_t i = begin, j = end;
    for (;;) {
        while (i < j && goesLeft(refs[i])) left.add(refs[i++]);
        while (i < j && !goesLeft(refs[j - 1])) right.add(refs[--j]);
        if (i >= j) break;
        std::swap(refs[i], refs[j - 1]);
        left.add(refs[i++]);
        right.add(refs[--j]);
    }
    return i;
}

std::uint32_t ceilLog2(std::uint64_t n)
{
    std::uint32_t k = 0;
    while ((std::uint64_t{1} << k) < n) ++k;
    return k;
}

void setBounds(BvhNode& node, const Aabb& box)
{
    for (int a = 0; a < 3; ++a) {
        node.lo[a] = box.lo[a];
        node.hi[a] = box.hi[a];
    }
}

}  // namespace

Bvh buildBvh(const std::vector<Aabb>& primitiveBounds, std::uint32_t maxLeafSize)
{
    if (primitiveBounds.size() > std::uint64_t{0xFFFFFFFFu}) throw std::length_error("buildBvh: more than 2^32 - 1 primitives");
    const auto n = static_cast<std::uint32_t>(primitiveBounds.size());
    maxLeafSize = std::max<std::uint32_t>(maxLeafSize, 1);

    Bvh bvh;
    if (n == 0) {
        BvhNode root{};
        setBounds(root, Aabb{});
        root.leftOrFirst = 0;
        root.count = 0;
        bvh.nodes.push_back(root);
        return bvh;
    }

    std::vector<PrimRef> refs(n);
    Bounds rootBounds;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Aabb& b = primitiveBounds[i];
        PrimRef& r = refs[i];
        r.index = i;
        if (b.valid()) {
            r.box = b;
            r.centroid = b.center();
        } else {
            r.box = Aabb{};
            r.centroid = glm::vec3(0.f);
        }
        rootBounds.add(r);
    }
    // Nodes at depth >= medianDepth split by object median, which bounds the depth of what is
    // left by ceil(log2 n) levels: every node then lies at depth < kBvhMaxDepth.
    const std::uint32_t medianDepth = kBvhMaxDepth - 1 - ceilLog2(n);

    bvh.nodes.reserve(std::size_t{2} * n / std::max<std::uint32_t>(1, maxLeafSize / 2) + 1);
    bvh.nodes.push_back(BvhNode{});
    std::vector<Task> stack;
    stack.push_back(Task{0, 0, n, 0, rootBounds});
    while (!stack.empty()) {
        const Task t = stack.back();
        stack.pop_back();
        const std::uint32_t count = t.end - t.begin;
        setBounds(bvh.nodes[t.node], t.bounds.box);

        auto makeLeaf = [&] {
            bvh.nodes[t.node].leftOrFirst = t.begin;
            bvh.nodes[t.node].count = count;
        };
        if (count <= 1 || (t.depth >= medianDepth && count <= maxLeafSize)) {
            makeLeaf();
            continue;
        }

        Bounds left, right;
        std::uint32_t mid = t.begin;
        Split split;
        if (t.depth < medianDepth) split = findSahSplit(refs.data() + t.begin, count, t.bounds);
        const float leafCost = kIntersectionCost * float(count);
        if (split.axis >= 0 && (split.cost < leafCost || count > maxLeafSize)) {
            const int a = split.axis;
            const float lo = t.bounds.cbox.lo[a];
            const float scale = float(kBins) / t.bounds.cbox.extent()[a];
            mid = partition(
                refs, t.begin, t.end, [&](const PrimRef& r) { return binOf(r.centroid[a], lo, scale) < split.bin; }, left, right);
        } else if (count > maxLeafSize) {
            // No separating plane (all centroids equal, or below binning resolution) or the depth
            // limit: object median along the widest centroid axis.
            const int a = t.bounds.cbox.largestAxis();
            mid = t.begin + count / 2;
            std::nth_element(refs.begin() + t.begin, refs.begin() + mid, refs.begin() + t.end,
                             [a](const PrimRef& x, const PrimRef& y) { return x.centroid[a] < y.centroid[a]; });
            for (std::uint32_t i = t.begin; i < mid; ++i) left.add(refs[i]);
            for (std::uint32_t i = mid; i < t.end; ++i) right.add(refs[i]);
        } else {
            makeLeaf();
            continue;
        }

        const auto leftIndex = static_cast<std::uint32_t>(bvh.nodes.size());
        bvh.nodes.push_back(BvhNode{});
        bvh.nodes.push_back(BvhNode{});
        bvh.nodes[t.node].leftOrFirst = leftIndex;
        bvh.nodes[t.node].count = 0;
        // Right pushed first so the left subtree is built (and laid out) first.
        stack.push_back(Task{leftIndex + 1, mid, t.end, t.depth + 1, right});
        stack.push_back(Task{leftIndex, t.begin, mid, t.depth + 1, left});
    }

    bvh.order.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) bvh.order[i] = refs[i].index;
    return bvh;
}

std::uint32_t bvhDepth(const Bvh& bvh)
{
    if (bvh.nodes.empty()) return 0;
    std::uint32_t levels = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{0u, 1u}};
    while (!stack.empty()) {
        const auto [node, level] = stack.back();
        stack.pop_back();
        levels = std::max(levels, level);
        const BvhNode& nd = bvh.nodes[node];
        if (!nd.isLeaf() && nd.leftOrFirst + 1 < bvh.nodes.size()) {
            stack.emplace_back(nd.leftOrFirst, level + 1);
            stack.emplace_back(nd.leftOrFirst + 1, level + 1);
        }
    }
    return levels;
}

double bvhSahCost(const Bvh& bvh)
{
    if (bvh.nodes.empty() || bvh.order.empty()) return 0.0;
    const double rootArea = bvh.nodes[0].bounds().surfaceArea();
    if (!(rootArea > 0.0)) return double(bvh.order.size());
    double cost = 0.0;
    for (const BvhNode& node : bvh.nodes) {
        const double rel = node.bounds().surfaceArea() / rootArea;
        cost += node.isLeaf() ? rel * kIntersectionCost * node.count : rel * kTraversalCost;
    }
    return cost;
}

}  // namespace oas::scene
