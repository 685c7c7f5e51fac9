// tests/golden/patterns.json checked three ways: the C++ API (oas::makePattern, oas::sample and
// the CPU fast path), the GLSL library on the Vulkan device (GoldenGpu), and independently of our
// code: each word is recomputed here from its definition in docs/PATTERN.md with naive
// arithmetic of its own (GoldenSpec). The C builder is checked by tests/c/pattern_c_test.c.
// The file freezes the samples: a change to any value must be deliberate (regenerate with
// oas-golden-writer and bump the minor version), since users' images and other ports depend on it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "golden/golden_cases.hpp"
#include "gpu_test_support.hpp"
#include <cstring>

#include "golden_points_spv.h"
#include "oas/pattern.hpp"

#ifndef OAS_GOLDEN_FILE
#error "define OAS_GOLDEN_FILE"
#endif

namespace {

using nlohmann::json;

const json& golden()
{
    static const json doc = [] {
        std::ifstream in(OAS_GOLDEN_FILE);
        if (!in) throw std::runtime_error("cannot open " + std::string(OAS_GOLDEN_FILE));
        return json::parse(in);
    }();
    return doc;
}

oas::PatternRequest requestOf(const json& c)
{
    oas::PatternRequest r;
    r.sampler = c["request"]["sampler"].get<std::string>();
    r.spp = c["request"]["spp"];
    r.strength = c["request"]["strength"];
    r.offset = c["request"]["offset"].get<std::string>();
    r.dims = c["request"]["dims"];
    return r;
}

oas::Pattern patternOf(const json& c)
{
    const auto w = c["words"].get<std::vector<std::uint32_t>>();
    oas::Pattern p;
    std::uint32_t* dst = &p.construction;
    for (std::size_t i = 0; i < 16; ++i) dst[i] = w.at(i);
    return p;
}

std::uint32_t toF(float v)
{
    return std::uint32_t(std::ldexp(double(v), 24));
}

TEST(Golden, TheFileHoldsEveryCaseOfTheList)
{
    const auto& cases = golden()["cases"];
    ASSERT_EQ(cases.size(), oas::golden::cases().size());
    std::map<std::string, int> seen;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const auto& want = oas::golden::cases()[i];
        const auto r = requestOf(cases[i]);
        EXPECT_EQ(r.sampler, want.sampler);
        EXPECT_EQ(r.spp, want.spp);
        EXPECT_EQ(r.offset, want.offset);
        ++seen[r.sampler];
    }
    for (const auto& name : oas::samplerNames()) EXPECT_GT(seen[name], 0) << name << " has no golden case";
    EXPECT_EQ(golden()["pixel"]["pixelSeed"].get<std::uint32_t>(),
              oas::pixelSeed(oas::golden::kPixelX, oas::golden::kPixelY, oas::golden::kSeed));
}

TEST(Golden, CppPatternsAndSamplesMatch)
{
    const std::uint32_t seed = golden()["pixel"]["pixelSeed"];
    for (const auto& c : golden()["cases"]) {
        SCOPED_TRACE(c["describe"].get<std::string>());
        const oas::Pattern p = oas::makePattern(requestOf(c));
        const std::uint32_t* words = &p.construction;
        EXPECT_EQ(std::vector<std::uint32_t>(words, words + 16), c["words"].get<std::vector<std::uint32_t>>());
        const auto indices = c["indices"].get<std::vector<std::uint32_t>>();
        const auto dims = c["dims"].get<std::vector<std::uint32_t>>();
        // oas_sample one value at a time ...
        for (std::size_t i = 0; i < indices.size(); ++i)
            for (std::size_t d = 0; d < dims.size(); ++d)
                EXPECT_EQ(toF(oas::sample(p, seed, indices[i], dims[d])), c["F"][i][d].get<std::uint32_t>())
                    << "index " << indices[i] << " dim " << dims[d];
        // ... and the hoisted path generateCpu takes (block and column state per pass).
        oas::SampleRequest r;
        r.x0 = oas::golden::kPixelX;
        r.y0 = oas::golden::kPixelY;
        r.seed = oas::golden::kSeed;
        r.spp = indices.back() + 1;
        r.dims = dims.back() + 1;
        std::vector<float> all(std::size_t(r.spp) * r.dims);
        oas::generateCpu(p, r, all.data(), 1);
        for (std::size_t i = 0; i < indices.size(); ++i)
            for (std::size_t d = 0; d < dims.size(); ++d)
                EXPECT_EQ(toF(all[std::size_t(indices[i]) * r.dims + dims[d]]), c["F"][i][d].get<std::uint32_t>())
                    << "generateCpu, index " << indices[i] << " dim " << dims[d];
    }
}

class GoldenGpu : public oas::test::GpuTest {};

TEST_F(GoldenGpu, GlslSamplesMatch)
{
    oas::vk::Context& ctx = *oas::test::gpuState().context;
    struct Push {
        oas::Pattern pattern;
        std::uint32_t pixelSeed, count;
    };
    oas::vk::ComputePipeline pipeline(ctx, golden_points_spv, sizeof(golden_points_spv), 3, sizeof(Push));
    const auto& directions = oas::sobolDirections();
    oas::vk::Buffer sobol(ctx, directions.size() * sizeof(std::uint32_t));
    std::memcpy(sobol.data(), directions.data(), directions.size() * sizeof(std::uint32_t));
    const std::uint32_t seed = golden()["pixel"]["pixelSeed"];
    for (const auto& c : golden()["cases"]) {
        SCOPED_TRACE(c["describe"].get<std::string>());
        const auto indices = c["indices"].get<std::vector<std::uint32_t>>();
        const auto dims = c["dims"].get<std::vector<std::uint32_t>>();
        std::vector<std::uint32_t> points;
        for (auto i : indices)
            for (auto d : dims) points.insert(points.end(), {i, d});
        const std::uint32_t count = std::uint32_t(points.size() / 2);
        oas::vk::Buffer in(ctx, points.size() * sizeof(std::uint32_t)), out(ctx, count * sizeof(float));
        std::memcpy(in.data(), points.data(), points.size() * sizeof(std::uint32_t));
        std::memset(out.data(), 0xff, count * sizeof(float));  // NaN until written
        const Push push{patternOf(c), seed, count};            // the file's words, uploaded as they are
        oas::vk::Buffer* buffers[] = {&in, &out, &sobol};
        ctx.dispatch(pipeline, buffers, &push, sizeof(push), (count + 7) / 8);
        const auto* got = static_cast<const float*>(out.data());
        for (std::size_t i = 0, k = 0; i < indices.size(); ++i)
            for (std::size_t d = 0; d < dims.size(); ++d, ++k)
                EXPECT_EQ(toF(got[k]), c["F"][i][d].get<std::uint32_t>()) << "index " << indices[i] << " dim " << dims[d];
    }
}

// ---- The words from their definitions (docs/PATTERN.md), with arithmetic written for this test.

/// GF(p^k) elements as base-p digit vectors, reduced by x^k = g(x): schoolbook, no shortcuts.
struct NaiveField {
    std::uint32_t p, k, g;
    std::vector<std::uint32_t> digits(std::uint32_t a) const
    {
        std::vector<std::uint32_t> d(k);
        for (auto& x : d) {
            x = a % p;
            a /= p;
        }
        return d;
    }
    std::uint32_t value(const std::vector<std::uint32_t>& d) const
    {
        std::uint32_t v = 0;
        for (std::size_t i = d.size(); i-- > 0;) v = v * p + d[i];
        return v;
    }
    std::uint32_t mul(std::uint32_t a, std::uint32_t b) const
    {
        const auto x = digits(a), y = digits(b), gd = digits(g);
        std::vector<std::uint32_t> prod(2 * k, 0);
        for (std::uint32_t i = 0; i < k; ++i)
            for (std::uint32_t j = 0; j < k; ++j) prod[i + j] = (prod[i + j] + x[i] * y[j]) % p;
        for (std::uint32_t deg = 2 * k - 1; deg >= k; --deg) {  // x^deg = x^(deg-k) g(x)
            const std::uint32_t c = prod[deg];
            prod[deg] = 0;
            for (std::uint32_t i = 0; i < k; ++i) prod[deg - k + i] = (prod[deg - k + i] + c * gd[i]) % p;
        }
        prod.resize(k);
        return value(prod);
    }
    bool xIsPrimitive() const
    {
        if (k == 1) return true;
        std::uint32_t q = 1;
        for (std::uint32_t i = 0; i < k; ++i) q *= p;
        const std::uint32_t x = p;  // the element x: digits (0, 1, 0, ...)
        std::uint32_t power = 1;
        for (std::uint32_t e = 1; e < q - 1; ++e) {
            power = mul(power, x);
            if (power == 1) return false;
        }
        return mul(power, x) == 1;
    }
};

bool isPrime(std::uint32_t n)
{
    for (std::uint32_t d = 2; d * d <= n; ++d)
        if (n % d == 0) return false;
    return n >= 2;
}

/// q = p^k, p prime: dividing out q's smallest divisor (a prime) leaves 1.
bool isPrimePower(std::uint32_t q)
{
    if (q < 2) return false;
    std::uint32_t p = 2;
    while (p <= q && q % p != 0) ++p;
    while (q > 1 && q % p == 0) q /= p;
    return q == 1;
}

void expectDivisor(std::uint32_t d, std::uint32_t recip, std::uint32_t shift, const char* what)
{
    std::mt19937 rng(d);
    std::vector<std::uint32_t> xs = {0, 1, d - 1, d, d + 1, 0xffffffffu, 0xfffffffeu, 0x80000000u};
    for (int i = 0; i < 2000; ++i) xs.push_back(rng());
    for (std::uint32_t x : xs) {
        const std::uint32_t t = std::uint32_t((std::uint64_t(x) * recip) >> 32);
        const std::uint32_t q = shift == 0 ? t + (x - t) : (t + ((x - t) >> 1)) >> (shift - 1);
        ASSERT_EQ(q, x / d) << what << ": d = " << d << ", x = " << x;
    }
}

TEST(GoldenSpec, EveryWordFollowsFromItsDefinition)
{
    const std::map<std::string, std::uint32_t> codes = {
        {"bose", 1},     {"bush", 2},    {"bose-bush", 3},   {"addelman-kempthorne", 4},
        {"cmjnd", 5},    {"random", 16}, {"jittered2d", 17}, {"cmj2d", 18},
        {"zerotwo", 19}, {"halton", 20}, {"sobol-owen", 21}, {"sobol", 22}, {"sobol-burley", 23},
        {"faure", 24}};
    const std::map<std::string, std::uint32_t> offsets = {{"centered", 0}, {"j", 1}, {"mj", 2}, {"cmj", 3}};
    for (const auto& c : golden()["cases"]) {
        SCOPED_TRACE(c["describe"].get<std::string>());
        const auto r = requestOf(c);
        const oas::Pattern w = patternOf(c);
        const std::uint32_t code = codes.at(r.sampler);
        const bool oa = code < 16, faure = code == 24;
        EXPECT_EQ(w.construction, code);
        if (!faure) {
            EXPECT_EQ(w.N, r.spp);
        }
        EXPECT_EQ(w.offset, oa ? offsets.at(r.offset) : 0u);
        const std::uint32_t s = w.s, t = w.strength, N = w.N;
        if (faure) {
            // d dims a block (the strength; by default the request's dims within 2 .. 16), base q
            // the smallest prime power >= d, N = q^K the smallest power of q >= spp, K in aux.
            const std::uint32_t d = r.strength ? r.strength : std::clamp(r.dims, 2u, 16u);
            EXPECT_EQ(t, d);
            EXPECT_EQ(w.blockDims, d);
            std::uint32_t q = std::max(d, 2u);
            while (!isPrimePower(q)) ++q;
            EXPECT_EQ(s, q);
            std::uint32_t n = q, k = 1;
            while (n < r.spp) n *= q, ++k;
            EXPECT_EQ(N, n);
            EXPECT_EQ(w.aux, k);
            EXPECT_EQ(w.aux2, 0u);
        }
        if (oa || faure) {
            if (oa) {
                EXPECT_EQ(w.aux2, N / s) << "aux2 = N / s for the OAs";
            }
            std::uint64_t st = 1;
            for (std::uint32_t i = 0; i < t; ++i) st *= s;
            const std::uint32_t q = code == 3 ? 2 * s : s;  // Bose-Bush: GF(2q)
            if (code != 5) {
                // q = p^k with p prime, and x^k = fieldPoly(x) the first g (counting up) making x primitive.
                std::uint32_t pk = 1;
                for (std::uint32_t i = 0; i < w.fieldK; ++i) pk *= w.fieldP;
                EXPECT_TRUE(isPrime(w.fieldP));
                EXPECT_EQ(pk, q);
                EXPECT_EQ(w.fieldQ, q);
                if (w.fieldK == 1) {
                    EXPECT_EQ(w.fieldPoly, 0u);
                } else {
                    EXPECT_TRUE((NaiveField{w.fieldP, w.fieldK, w.fieldPoly}.xIsPrimitive()));
                    for (std::uint32_t g = 1; g < w.fieldPoly; ++g) {
                        if (g % w.fieldP == 0) continue;
                        EXPECT_FALSE((NaiveField{w.fieldP, w.fieldK, g}.xIsPrimitive())) << "smaller g " << g;
                    }
                }
            }
            switch (code) {
            case 1:
                EXPECT_EQ(t, 2u);
                EXPECT_EQ(N, s * s);
                EXPECT_EQ(w.blockDims, s + 1);
                break;
            case 2:
                EXPECT_EQ(N, st);
                EXPECT_EQ(w.blockDims, s + 1);
                EXPECT_EQ(w.aux, N / s);
                break;
            case 3:
                EXPECT_EQ(t, 2u);
                EXPECT_EQ(N, 2 * s * s);
                EXPECT_EQ(w.blockDims, 2 * s + 1);
                break;
            case 4: {
                EXPECT_EQ(t, 2u);
                EXPECT_EQ(N, 2 * s * s);
                EXPECT_EQ(w.blockDims, 2 * s + 1);
                // aux: the smallest element that is not a square.
                const NaiveField f{w.fieldP, w.fieldK, w.fieldPoly};
                std::vector<bool> square(q, false);
                for (std::uint32_t x = 0; x < q; ++x) square[f.mul(x, x)] = true;
                std::uint32_t smallest = 0;
                while (square[smallest]) ++smallest;
                EXPECT_EQ(w.aux, smallest);
                break;
            }
            case 5:
                EXPECT_EQ(N, st);
                EXPECT_EQ(w.blockDims, t);
                EXPECT_EQ(t, r.strength ? r.strength : r.dims);
                break;
            }
        } else if (!faure) {
            EXPECT_EQ(s, N);
            EXPECT_EQ(w.blockDims, code == 20 ? 32u : code == 21 || code == 22 ? 1024u : code == 23 ? 4u : code == 16 ? 1u : 2u);
            EXPECT_EQ(w.strength, code == 16 ? 0u : code >= 20 ? 1u : 2u);
            // The grid nx x ny = N: nx the largest divisor of N with nx * nx <= N.
            std::uint32_t nx = 1;
            for (std::uint32_t d = 1; d * d <= N; ++d)
                if (N % d == 0) nx = d;
            EXPECT_EQ(w.aux, nx);
            EXPECT_EQ(w.aux2, N / nx);
        }
        expectDivisor(s, w.recipS, w.recipShifts & 0xff, "s");
        expectDivisor(std::max(w.fieldP, 1u), w.recipP, (w.recipShifts >> 8) & 0xff, "p");
        expectDivisor(N, w.recipN, (w.recipShifts >> 16) & 0xff, "N");
        EXPECT_EQ(w.recipShifts >> 24, 0u);
        for (const auto& row : c["F"])
            for (const auto& f : row) EXPECT_LT(f.get<std::uint32_t>(), 1u << 24) << "a value F / 2^24 must be < 1";
    }
}

}  // namespace
