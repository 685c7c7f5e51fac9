// BVH builder and CPU traversal (host/scene/bvh.hpp): structural invariants, ray queries against
// brute force, edge cases (empty, single, identical, flat, point, empty boxes, adversarial depth),
// SAH sanity and a 1e6-primitive build.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "scene/bvh.hpp"

namespace {

using oas::scene::Aabb;
using oas::scene::buildBvh;
using oas::scene::Bvh;
using oas::scene::BvhNode;
using oas::scene::traverse;

constexpr float kInf = std::numeric_limits<float>::infinity();

Aabb box(glm::vec3 lo, glm::vec3 hi)
{
    return Aabb{lo, hi};
}

bool sameBox(const Aabb& a, const Aabb& b)
{
    if (a.empty() && b.empty()) return true;
    return a.lo == b.lo && a.hi == b.hi;
}

// Checks every structural property the builder promises; returns the number of leaves.
std::size_t checkInvariants(const Bvh& bvh, const std::vector<Aabb>& prims, std::uint32_t maxLeafSize)
{
    const std::size_t n = prims.size();
    maxLeafSize = std::max<std::uint32_t>(maxLeafSize, 1);
    EXPECT_FALSE(bvh.nodes.empty());
    if (bvh.nodes.empty()) return 0;
    EXPECT_EQ(bvh.order.size(), n);
    if (n == 0) {
        EXPECT_EQ(bvh.nodes.size(), 1u);
        EXPECT_TRUE(bvh.nodes[0].isLeaf() || bvh.nodes[0].count == 0);
        EXPECT_EQ(bvh.nodes[0].count, 0u);
        EXPECT_TRUE(bvh.nodes[0].bounds().empty());
        return 1;
    }

    // Every primitive exactly once in `order`.
    std::vector<int> seen(n, 0);
    for (std::uint32_t p : bvh.order) {
        EXPECT_LT(p, n);
        if (p < n) ++seen[p];
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));

    // Walk the tree: every node reached once, children in range and adjacent, leaves nonempty
    // and capped, leaf ranges cover `order` exactly once, boxes contain (and equal the union of)
    // what is below them, depth within the traversal stack.
    std::vector<int> reached(bvh.nodes.size(), 0);
    std::vector<int> covered(n, 0);
    std::size_t leaves = 0;
    struct Item {
        std::uint32_t node, depth;
    };
    std::vector<Item> stack{{0, 0}};
    bool ok = true;
    while (!stack.empty() && ok) {
        const Item it = stack.back();
        stack.pop_back();
        ok = it.node < bvh.nodes.size();
        EXPECT_TRUE(ok) << "node index " << it.node;
        if (!ok) break;
        ++reached[it.node];
        EXPECT_LT(it.depth, oas::scene::kBvhMaxDepth);
        const BvhNode& nd = bvh.nodes[it.node];
        const Aabb nb = nd.bounds();
        Aabb unionBelow;
        if (nd.isLeaf()) {
            ++leaves;
            EXPECT_LE(nd.count, maxLeafSize);
            EXPECT_LE(std::uint64_t{nd.leftOrFirst} + nd.count, n);
            for (std::uint32_t i = nd.leftOrFirst; i < nd.leftOrFirst + nd.count && i < n; ++i) {
                ++covered[i];
                const Aabb& pb = prims[bvh.order[i]];
                if (pb.valid()) {
                    EXPECT_TRUE(nb.contains(pb));
                    unionBelow.extend(pb);
                }
            }
        } else {
            const std::uint32_t l = nd.leftOrFirst;
            ok = l > it.node && std::size_t{l} + 1 < bvh.nodes.size();
            EXPECT_TRUE(ok) << "node " << it.node << " children " << l;
            if (!ok) break;
            EXPECT_TRUE(nb.contains(bvh.nodes[l].bounds()));
            EXPECT_TRUE(nb.contains(bvh.nodes[l + 1].bounds()));
            unionBelow.extend(bvh.nodes[l].bounds());
            unionBelow.extend(bvh.nodes[l + 1].bounds());
            stack.push_back({l, it.depth + 1});
            stack.push_back({l + 1, it.depth + 1});
        }
        EXPECT_TRUE(sameBox(nb, unionBelow)) << "node " << it.node << " not tight";
    }
    EXPECT_TRUE(std::all_of(reached.begin(), reached.end(), [](int c) { return c == 1; }))
        << "every node must be reached exactly once";
    EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }))
        << "leaf ranges must partition `order`";
    EXPECT_LT(oas::scene::bvhDepth(bvh), oas::scene::kBvhMaxDepth + 1);
    return leaves;
}

// Primitive = its own box; uses the same slab test as the traversal, so hits are consistent.
bool hitBox(const Aabb& b, const glm::vec3& o, const glm::vec3& invDir, float tMax, float& t)
{
    BvhNode nd{};
    for (int a = 0; a < 3; ++a) {
        nd.lo[a] = b.lo[a];
        nd.hi[a] = b.hi[a];
    }
    return oas::scene::intersectNode(nd, o, invDir, 0.f, tMax, t);
}

struct Sphere {
    glm::vec3 c;
    float r;
};

bool hitSphere(const Sphere& s, const glm::vec3& o, const glm::vec3& d, float tMax, float& t)
{
    const glm::vec3 oc = o - s.c;
    const float a = glm::dot(d, d), b = glm::dot(oc, d), c = glm::dot(oc, oc) - s.r * s.r;
    const float disc = b * b - a * c;
    if (disc < 0.f) return false;
    const float sq = std::sqrt(disc);
    float root = (-b - sq) / a;
    if (root < 0.f) root = (-b + sq) / a;
    if (root < 0.f || root > tMax) return false;
    t = root;
    return true;
}

struct Ray {
    glm::vec3 o, d;
    float tMax;
};

// Random rays from around [-1,1]^3 (some inside), some with zero (and -0) direction components.
std::vector<Ray> randomRays(std::mt19937& rng, int count, float extent = 1.5f)
{
    std::uniform_real_distribution<float> u(-extent, extent), n(-1.f, 1.f), u01(0.f, 1.f);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        Ray r{{u(rng), u(rng), u(rng)}, {n(rng), n(rng), n(rng)}, kInf};
        const float kind = u01(rng);
        if (kind < 0.1f)
            r.d[i % 3] = 0.f;
        else if (kind < 0.15f)
            r.d[i % 3] = -0.f;
        else if (kind < 0.2f)
            r.d[i % 3] = r.d[(i + 1) % 3] = 0.f;
        if (r.d == glm::vec3(0.f)) r.d.x = 1.f;
        if (u01(rng) < 0.3f) r.tMax = 3.f * u01(rng);
        rays.push_back(r);
    }
    return rays;
}

std::vector<Aabb> randomBoxes(std::mt19937& rng, int count, float minSize, float maxSize)
{
    std::uniform_real_distribution<float> pos(-1.f, 1.f), size(minSize, maxSize);
    std::vector<Aabb> boxes;
    for (int i = 0; i < count; ++i) {
        const glm::vec3 c{pos(rng), pos(rng), pos(rng)};
        const glm::vec3 h{size(rng), size(rng), size(rng)};
        boxes.push_back(box(c - h, c + h));
    }
    return boxes;
}

struct Hit {
    bool hit = false;
    float t = kInf;
};

Hit closestBoxBvh(const Bvh& bvh, const std::vector<Aabb>& prims, const Ray& r)
{
    const glm::vec3 inv = oas::scene::safeInverse(r.d);
    Hit h;
    traverse(bvh, r.o, r.d, r.tMax, [&](std::uint32_t p, float& tMax) {
        float t;
        if (hitBox(prims[p], r.o, inv, tMax, t) && t <= tMax) {
            h = {true, t};
            tMax = t;
        }
    });
    return h;
}

Hit closestBoxBrute(const std::vector<Aabb>& prims, const Ray& r)
{
    const glm::vec3 inv = oas::scene::safeInverse(r.d);
    Hit h;
    float tMax = r.tMax;
    for (const Aabb& b : prims) {
        float t;
        if (hitBox(b, r.o, inv, tMax, t) && t <= tMax) {
            h = {true, t};
            tMax = t;
        }
    }
    return h;
}

// Every primitive whose box the ray touches in [0, tMax] must be offered by the traversal.
void expectConservative(const Bvh& bvh, const std::vector<Aabb>& prims, const Ray& r)
{
    std::vector<char> offered(prims.size(), 0);
    traverse(bvh, r.o, r.d, r.tMax, [&](std::uint32_t p, float&) { offered[p] = 1; });
    const glm::vec3 inv = oas::scene::safeInverse(r.d);
    for (std::size_t p = 0; p < prims.size(); ++p) {
        float t;
        if (hitBox(prims[p], r.o, inv, r.tMax, t)) {
            ASSERT_TRUE(offered[p]) << "primitive " << p << " missed; ray o=(" << r.o.x << "," << r.o.y << "," << r.o.z << ") d=("
                                    << r.d.x << "," << r.d.y << "," << r.d.z << ")";
        }
    }
}

// ---------------------------------------------------------------------------------------------

TEST(Bvh, NodeLayoutIsTwoVec4s)
{
    static_assert(sizeof(BvhNode) == 32);
    BvhNode nd{{1.f, 2.f, 3.f}, 7u, {4.f, 5.f, 6.f}, 9u};
    float f[8];
    std::memcpy(f, &nd, sizeof f);
    EXPECT_EQ(f[0], 1.f);
    EXPECT_EQ(f[2], 3.f);
    EXPECT_EQ(f[4], 4.f);
    EXPECT_EQ(f[6], 6.f);
    std::uint32_t w[8];
    std::memcpy(w, &nd, sizeof w);
    EXPECT_EQ(w[3], 7u);
    EXPECT_EQ(w[7], 9u);
}

TEST(Bvh, AabbBasics)
{
    Aabb e;
    EXPECT_TRUE(e.empty());
    EXPECT_EQ(e.surfaceArea(), 0.f);
    Aabb b = box({0, 0, 0}, {1, 2, 3});
    EXPECT_FLOAT_EQ(b.surfaceArea(), 2.f * (2 + 6 + 3));
    EXPECT_EQ(b.largestAxis(), 2);
    e.extend(b);
    EXPECT_TRUE(sameBox(e, b));
    Aabb flat = box({0, 0, 5}, {1, 1, 5});
    EXPECT_TRUE(flat.valid());
    EXPECT_FLOAT_EQ(flat.surfaceArea(), 2.f);
    EXPECT_TRUE(b.contains(Aabb{}));
    EXPECT_FALSE(b.contains(flat));
}

TEST(Bvh, SlabTestIsRobustToZeroDirections)
{
    using oas::scene::intersectNode;
    using oas::scene::safeInverse;
    BvhNode unit{{0, 0, 0}, 0, {1, 1, 1}, 1};
    BvhNode flat{{0, 0, 0}, 0, {1, 1, 0}, 1};  // in the plane z = 0
    float t;
    // Along +x through the middle.
    EXPECT_TRUE(intersectNode(unit, {-1, .5f, .5f}, safeInverse({1, 0, 0}), 0, kInf, t));
    EXPECT_FLOAT_EQ(t, 1.f);
    // -0 components behave like +0.
    EXPECT_TRUE(intersectNode(unit, {-1, .5f, .5f}, safeInverse({1, -0.f, -0.f}), 0, kInf, t));
    EXPECT_FLOAT_EQ(t, 1.f);
    EXPECT_TRUE(intersectNode(unit, {2, .5f, .5f}, safeInverse({-1, -0.f, 0.f}), 0, kInf, t));
    EXPECT_FLOAT_EQ(t, 1.f);
    // Parallel to a slab and outside it: miss.
    EXPECT_FALSE(intersectNode(unit, {-1, 1.5f, .5f}, safeInverse({1, 0, 0}), 0, kInf, t));
    EXPECT_FALSE(intersectNode(unit, {-1, -.5f, .5f}, safeInverse({1, -0.f, 0}), 0, kInf, t));
    // Running exactly in a face plane (0 * inf = NaN inside): closed box, hit.
    EXPECT_TRUE(intersectNode(unit, {-1, 0, .5f}, safeInverse({1, 0, 0}), 0, kInf, t));
    EXPECT_TRUE(intersectNode(unit, {-1, 1, .5f}, safeInverse({1, -0.f, 0}), 0, kInf, t));
    EXPECT_TRUE(intersectNode(flat, {-1, .5f, 0}, safeInverse({1, 0, 0}), 0, kInf, t));
    EXPECT_TRUE(intersectNode(flat, {-1, .5f, 0}, safeInverse({1, 0, -0.f}), 0, kInf, t));
    EXPECT_FLOAT_EQ(t, 1.f);
    EXPECT_FALSE(intersectNode(flat, {-1, .5f, 1e-6f}, safeInverse({1, 0, 0}), 0, kInf, t));
    // Through a flat box perpendicular to it.
    EXPECT_TRUE(intersectNode(flat, {.5f, .5f, 2}, safeInverse({0, 0, -1}), 0, kInf, t));
    EXPECT_FLOAT_EQ(t, 2.f);
    // Behind the origin or beyond tMax: miss; origin inside: entry 0.
    EXPECT_FALSE(intersectNode(unit, {2, .5f, .5f}, safeInverse({1, 0, 0}), 0, kInf, t));
    EXPECT_FALSE(intersectNode(unit, {-1, .5f, .5f}, safeInverse({1, 0, 0}), 0, .5f, t));
    EXPECT_TRUE(intersectNode(unit, {.5f, .5f, .5f}, safeInverse({0, 1, 0}), 0, kInf, t));
    EXPECT_EQ(t, 0.f);
    // Empty box (the empty tree's root): never hit, whatever the direction.
    BvhNode empty = {};
    for (int a = 0; a < 3; ++a) {
        empty.lo[a] = kInf;
        empty.hi[a] = -kInf;
    }
    for (glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(-1, -0.f, 0), glm::vec3(1, 2, -3)})
        EXPECT_FALSE(intersectNode(empty, {0, 0, 0}, safeInverse(d), 0, kInf, t));
}

TEST(Bvh, EmptyInput)
{
    std::vector<Aabb> prims;
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    int calls = 0;
    traverse(bvh, {0, 0, 0}, {1, 0, 0}, kInf, [&](std::uint32_t, float&) { ++calls; });
    traverse(bvh, {0, 0, 0}, {0, 0, 0}, kInf, [&](std::uint32_t, float&) { ++calls; });
    EXPECT_EQ(calls, 0);
    EXPECT_EQ(oas::scene::bvhDepth(bvh), 1u);
    EXPECT_EQ(oas::scene::bvhSahCost(bvh), 0.0);
}

TEST(Bvh, SinglePrimitive)
{
    std::vector<Aabb> prims{box({0, 0, 0}, {1, 1, 1})};
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].count, 1u);
    EXPECT_EQ(bvh.order, std::vector<std::uint32_t>{0});
    int calls = 0;
    traverse(bvh, {-1, .5f, .5f}, {1, 0, 0}, kInf, [&](std::uint32_t p, float&) {
        EXPECT_EQ(p, 0u);
        ++calls;
    });
    traverse(bvh, {-1, 5, .5f}, {1, 0, 0}, kInf, [&](std::uint32_t, float&) { ++calls; });
    EXPECT_EQ(calls, 1);
}

TEST(Bvh, IdenticalBoxesAreSplitByMedian)
{
    for (std::uint32_t maxLeaf : {0u, 1u, 4u, 16u}) {
        std::vector<Aabb> prims(1000, box({0, 0, 0}, {1, 1, 1}));
        Bvh bvh = buildBvh(prims, maxLeaf);
        checkInvariants(bvh, prims, maxLeaf);
        const std::uint32_t cap = std::max(maxLeaf, 1u);
        // Median splits: balanced, so the depth is about log2(n / cap).
        EXPECT_LE(oas::scene::bvhDepth(bvh), 1u + static_cast<std::uint32_t>(std::ceil(std::log2(1000.0 / cap))) + 1u);
        int calls = 0;
        traverse(bvh, {.5f, .5f, -1}, {0, 0, 1}, kInf, [&](std::uint32_t, float&) { ++calls; });
        EXPECT_EQ(calls, 1000);
    }
}

TEST(Bvh, IdenticalPointsAndEmptyBoxes)
{
    std::vector<Aabb> prims(100, box({1, 2, 3}, {1, 2, 3}));
    for (int i = 0; i < 20; ++i) prims.push_back(Aabb{});    // empty boxes
    prims.push_back(box({1, 1, 1}, {0, 0, 0}));              // inverted = empty
    prims.push_back(box({0, 0, 0}, {std::nanf(""), 1, 1}));  // NaN = empty
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    EXPECT_TRUE(sameBox(bvh.nodes[0].bounds(), box({1, 2, 3}, {1, 2, 3})));
    // A ray through the point finds all 100 point primitives.
    std::vector<char> offered(prims.size(), 0);
    traverse(bvh, {1, 2, 0}, {0, 0, 1}, kInf, [&](std::uint32_t p, float&) { offered[p] = 1; });
    for (int i = 0; i < 100; ++i) EXPECT_TRUE(offered[i]) << i;
}

TEST(Bvh, FlatBoxesInAPlane)
{
    // Triangles-on-a-floor situation: every box has zero z extent, all at z = 0.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-1.f, 1.f), size(0.f, 0.05f);
    std::vector<Aabb> prims;
    for (int i = 0; i < 3000; ++i) {
        const float x = pos(rng), y = pos(rng);
        prims.push_back(box({x, y, 0}, {x + size(rng), y + size(rng), 0}));
    }
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    // Rays through the plane, and rays lying in it (dir.z = +-0 with o.z = 0).
    std::vector<Ray> rays = randomRays(rng, 2000);
    for (std::size_t i = 0; i < rays.size(); i += 2) {
        rays[i].o.z = 0.f;
        rays[i].d.z = (i % 4 == 0) ? 0.f : -0.f;
        if (rays[i].d == glm::vec3(0.f)) rays[i].d.x = 1.f;
    }
    int hits = 0, inPlaneHits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        const Hit a = closestBoxBvh(bvh, prims, r), b = closestBoxBrute(prims, r);
        ASSERT_EQ(a.hit, b.hit) << "ray " << i;
        if (a.hit) {
            ASSERT_EQ(a.t, b.t) << "ray " << i;
            ++hits;
            inPlaneHits += i % 2 == 0;
        }
        expectConservative(bvh, prims, r);
    }
    EXPECT_GT(hits, 200);
    EXPECT_GT(inPlaneHits, 100);
}

TEST(Bvh, PointsOnALine)
{
    // Zero surface area everywhere: the builder ranks splits by extent sums instead.
    std::vector<Aabb> prims;
    for (int i = 0; i < 1000; ++i) {
        const float x = float(i % 500) * 0.01f;
        prims.push_back(box({x, 0, 0}, {x, 0, 0}));
    }
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    EXPECT_LE(oas::scene::bvhDepth(bvh), 16u);
    // A ray across the line at x = 1.23 is offered only the two points there (plus few more).
    std::vector<std::uint32_t> offered;
    traverse(bvh, {1.23f, 0, -1}, {0, 0, 1}, kInf, [&](std::uint32_t p, float&) { offered.push_back(p); });
    EXPECT_LE(offered.size(), 8u);
    int exact = 0;
    for (std::uint32_t p : offered) exact += prims[p].lo.x == 1.23f;
    EXPECT_EQ(exact, 2);
}

TEST(Bvh, DepthStaysBoundedOnExponentialSpacing)
{
    // Centroids at (2^i, 2^j): binned splits peel off only a few primitives per level, along x
    // and then along y, which unchecked gives a depth over 90. The median fallback near the
    // limit keeps every node at depth < kBvhMaxDepth for the GPU stack.
    std::vector<Aabb> prims;
    for (int i = -140; i < 127; i += 2) {
        for (int j = -140; j < 127; j += 2) {
            const float x = std::ldexp(1.f, i), y = std::ldexp(1.f, j);
            prims.push_back(box({x, y, 0}, {x * 1.5f, y * 1.5f, 1}));
        }
    }
    for (std::uint32_t maxLeaf : {1u, 4u}) {
        Bvh bvh = buildBvh(prims, maxLeaf);
        checkInvariants(bvh, prims, maxLeaf);
        EXPECT_LE(oas::scene::bvhDepth(bvh), oas::scene::kBvhMaxDepth);
        std::printf("exponential spacing, maxLeaf %u: depth %u\n", maxLeaf, oas::scene::bvhDepth(bvh));
        // Queries still agree with brute force.
        for (const auto& p : {prims[0], prims[200], prims[4000], prims.back()}) {
            Ray r{{p.lo.x, p.lo.y, -1}, {0, 0, 1}, kInf};
            const Hit a = closestBoxBvh(bvh, prims, r), b = closestBoxBrute(prims, r);
            EXPECT_EQ(a.hit, b.hit);
            EXPECT_EQ(a.t, b.t);
        }
    }
}

TEST(Bvh, RandomBoxesClosestHitMatchesBruteForce)
{
    std::mt19937 rng(1234);
    for (std::uint32_t maxLeaf : {1u, 4u, 8u}) {
        std::vector<Aabb> prims = randomBoxes(rng, 2000, 0.f, 0.04f);
        Bvh bvh = buildBvh(prims, maxLeaf);
        checkInvariants(bvh, prims, maxLeaf);
        int hits = 0;
        for (const Ray& r : randomRays(rng, 3000)) {
            const Hit a = closestBoxBvh(bvh, prims, r), b = closestBoxBrute(prims, r);
            ASSERT_EQ(a.hit, b.hit);
            if (a.hit) {
                ASSERT_EQ(a.t, b.t);
            }
            hits += a.hit;
        }
        for (const Ray& r : randomRays(rng, 300)) expectConservative(bvh, prims, r);
        EXPECT_GT(hits, 500);
    }
}

TEST(Bvh, RandomSpheresClosestHitMatchesBruteForce)
{
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> pos(-1.f, 1.f), rad(0.005f, 0.06f);
    std::vector<Sphere> spheres;
    std::vector<Aabb> prims;
    for (int i = 0; i < 4000; ++i) {
        Sphere s{{pos(rng), pos(rng), pos(rng)}, rad(rng)};
        // Pad by a hair so rounding in the sphere test never reaches outside the box.
        const glm::vec3 r(s.r * (1.f + 1e-4f));
        spheres.push_back(s);
        prims.push_back(box(s.c - r, s.c + r));
    }
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    int hits = 0;
    std::uint64_t offeredTotal = 0;
    const std::vector<Ray> rays = randomRays(rng, 5000);
    for (const Ray& r : rays) {
        Hit a, b;
        std::uint32_t ia = ~0u, ib = ~0u;
        traverse(bvh, r.o, r.d, r.tMax, [&](std::uint32_t p, float& tMax) {
            ++offeredTotal;
            float t;
            if (hitSphere(spheres[p], r.o, r.d, tMax, t)) {
                a = {true, t};
                ia = p;
                tMax = t;
            }
        });
        float tMax = r.tMax;
        for (std::uint32_t p = 0; p < spheres.size(); ++p) {
            float t;
            if (hitSphere(spheres[p], r.o, r.d, tMax, t)) {
                b = {true, t};
                ib = p;
                tMax = t;
            }
        }
        ASSERT_EQ(a.hit, b.hit);
        if (a.hit) {
            ASSERT_EQ(a.t, b.t);
            EXPECT_EQ(ia, ib);
        }
        hits += a.hit;
    }
    EXPECT_GT(hits, 1000);
    // The point of a BVH: far fewer candidates than primitives.
    const double perRay = double(offeredTotal) / double(rays.size());
    std::printf("spheres: %d/%zu rays hit, %.1f candidates per ray of %zu\n", hits, rays.size(), perRay, spheres.size());
    EXPECT_LT(perRay, 200.0);
}

TEST(Bvh, AnyHitStopsEarly)
{
    std::vector<Aabb> prims(50, box({0, 0, 0}, {1, 1, 1}));
    Bvh bvh = buildBvh(prims);
    int calls = 0;
    traverse(bvh, {.5f, .5f, -1}, {0, 0, 1}, kInf, [&](std::uint32_t, float&) {
        ++calls;
        return false;
    });
    EXPECT_EQ(calls, 1);
}

TEST(Bvh, SahSplitsBetweenClusters)
{
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<Aabb> prims;
    for (int i = 0; i < 1000; ++i) {
        // Cluster A around the origin, cluster B at +100 in y (not the first axis tried).
        const glm::vec3 c = glm::vec3(u(rng), u(rng), u(rng)) + (i % 2 ? glm::vec3(0, 100, 0) : glm::vec3(0));
        prims.push_back(box(c - 0.01f, c + 0.01f));
    }
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    const BvhNode& root = bvh.nodes[0];
    ASSERT_FALSE(root.isLeaf());
    Aabb l = bvh.nodes[root.leftOrFirst].bounds(), r = bvh.nodes[root.leftOrFirst + 1].bounds();
    if (l.lo.y > r.lo.y) std::swap(l, r);
    EXPECT_LT(l.hi.y, 2.f);
    EXPECT_GT(r.lo.y, 98.f);
    // Each child holds exactly one cluster.
    auto countBelow = [&](std::uint32_t node) {
        std::uint32_t c = 0;
        std::vector<std::uint32_t> st{node};
        while (!st.empty()) {
            const BvhNode& nd = bvh.nodes[st.back()];
            st.pop_back();
            if (nd.isLeaf())
                c += nd.count;
            else
                st.insert(st.end(), {nd.leftOrFirst, nd.leftOrFirst + 1});
        }
        return c;
    };
    EXPECT_EQ(countBelow(root.leftOrFirst), 500u);
    EXPECT_EQ(countBelow(root.leftOrFirst + 1), 500u);
}

TEST(Bvh, SahCostOfClusteredScene)
{
    // A dense cluster plus sparse outliers: the SAH cost must come out far below the cost of one
    // leaf holding everything (5000); it is at least 1, the root traversal itself.
    std::mt19937 rng(11);
    std::vector<Aabb> prims = randomBoxes(rng, 5000, 0.001f, 0.01f);
    for (Aabb& b : prims) {
        if (rng() % 10 != 0) {
            b.lo *= 0.05f;
            b.hi *= 0.05f;
        }
    }
    Bvh bvh = buildBvh(prims);
    checkInvariants(bvh, prims, 4);
    const double cost = oas::scene::bvhSahCost(bvh);
    std::printf("clustered scene: SAH cost %.2f (one leaf would be %zu)\n", cost, prims.size());
    EXPECT_GT(cost, 1.0);
    EXPECT_LT(cost, 100.0);
}

TEST(Bvh, MillionBoxes)
{
    std::mt19937 rng(2024);
    std::vector<Aabb> prims = randomBoxes(rng, 1'000'000, 0.0005f, 0.005f);
    const auto t0 = std::chrono::steady_clock::now();
    Bvh bvh = buildBvh(prims);
    const auto t1 = std::chrono::steady_clock::now();
    std::printf("built BVH over %zu boxes in %.3f s: %zu nodes, depth %u, SAH cost %.2f\n", prims.size(),
                std::chrono::duration<double>(t1 - t0).count(), bvh.nodes.size(), oas::scene::bvhDepth(bvh),
                oas::scene::bvhSahCost(bvh));
    checkInvariants(bvh, prims, 4);
    for (const Ray& r : randomRays(rng, 64)) {
        const Hit a = closestBoxBvh(bvh, prims, r), b = closestBoxBrute(prims, r);
        ASSERT_EQ(a.hit, b.hit);
        if (a.hit) {
            ASSERT_EQ(a.t, b.t);
        }
    }
}

}  // namespace
