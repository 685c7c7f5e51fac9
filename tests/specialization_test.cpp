// A shader specialized on one pattern kind and handed another is never silently wrong. An
// embedder's shader specialized for Bose 64 and given Bose 49 rendered a plausible image from wrong
// values (391 of 392 values differed from oas::sample; random given to a Bose pipeline: all): the
// specialized code folds away every other kind's branches. Now such a pattern gives NaN in every
// value (oas_specialized_value), and the C API says beforehand whether a pattern fits a
// specialization (oas_specialization_matches). For every construction, field kind, offset, large N
// and baseline, this specializes tests/shaders/specialized_consumer.comp on it and hands it every
// pattern of the list: values equal to the CPU twin's bit for bit where the C API says they
// match, all NaN where it says they do not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "gpu_test_support.hpp"
#include "oas/oas_pattern.h"
#include "oas/pattern.hpp"
#include "specialized_consumer_spv.h"
#include "specialized_consumer_two_blocks_spv.h"

namespace {

struct Push {
    oas::Pattern pattern;
    std::uint32_t spp, dims, seed, firstDim;
};

constexpr std::uint32_t kDims = 6;
constexpr std::uint32_t kMaxSamplesChecked = 64;
constexpr std::uint32_t kPixelSeed = 0x2545f491u;

oas::Pattern make(const char* sampler, std::uint32_t spp, const char* offset = "cmj", std::uint32_t strength = 0)
{
    oas::PatternRequest r;
    r.sampler = sampler;
    r.spp = spp;
    r.offset = offset;
    r.strength = strength;
    r.dims = kDims;
    return oas::makePattern(r);
}

/// One pattern per construction x field kind (prime, GF(2^k), GF(p^k) odd), every offset, an N
/// past 2^16 (OAS_STATIC_SMALL_N = 0) and every baseline.
std::vector<std::pair<std::string, oas::Pattern>> patterns()
{
    std::vector<std::pair<std::string, oas::Pattern>> list = {
        {"bose 49 cmj (prime)", make("bose", 49)},
        {"bose 64 cmj (GF(2^3))", make("bose", 64)},
        {"bose 81 mj (GF(3^2))", make("bose", 81, "mj")},
        {"bose 121 j", make("bose", 121, "j")},
        {"bose 49 centered", make("bose", 49, "centered")},
        {"bose 66049 cmj (N > 2^16)", make("bose", 66049)},
        {"bush 125 t=3 (prime)", make("bush", 125, "cmj", 3)},
        {"bush 512 t=3 (GF(2^3))", make("bush", 512, "cmj", 3)},
        {"bose-bush 32 (GF(2^2))", make("bose-bush", 32)},
        {"addelman-kempthorne 18 (prime)", make("addelman-kempthorne", 18)},
        {"addelman-kempthorne 162 (GF(3^2))", make("addelman-kempthorne", 162)},
        {"cmjnd 27 d=3", make("cmjnd", 27, "cmj", 3)},
    };
    for (const auto& name : oas::samplerNames())
        if (!oas::isOrthogonalArray(name)) list.push_back({name + " 16", make(name.c_str(), 16)});
    // Halton's digit loops stop at the bits of N - 1 (OAS_STATIC_INDEX_BITS): a shader made for
    // N = 16 (4 bits) must refuse N = 121 (7), one made for 121 must give 16's values.
    list.push_back({"halton 121", make("halton", 121)});
    // Faure's K digits are its OAS_STATIC_INDEX_BITS: "faure 16" above has d = kDims = 6, base 7,
    // K = 2; base 11 with K = 2 shares that specialization and must give its own values; base 3
    // with K = 4 must be refused by it and it by base 3's; GF(3^2) differs in its field.
    list.push_back({"faure 81 d=3 (K=4)", make("faure", 81, "cmj", 3)});
    list.push_back({"faure 81 d=9 (GF(3^2), K=2)", make("faure", 81, "cmj", 9)});
    list.push_back({"faure 100 d=10 (q=11, K=2)", make("faure", 100, "cmj", 10)});
    return list;
}

/// The consumer's six specialization constants for `pattern`, filled by the C API.
oas::vk::ComputePipeline::SpecConstants constantsFor(const oas::Pattern& pattern)
{
    OasSpecialization spec;
    oas_specialization(&pattern, &spec);
    return {{0, spec.construction}, {1, spec.offset}, {2, spec.fieldKind}, {3, spec.fieldDegree}, {4, spec.smallN}, {5, spec.indexBits}};
}

/// The Sobol direction table, where the consumer reads it (binding 1).
oas::vk::Buffer directionBuffer(oas::vk::Context& ctx)
{
    const auto& table = oas::sobolDirections();
    oas::vk::Buffer directions(ctx, table.size() * sizeof(std::uint32_t));
    std::memcpy(directions.data(), table.data(), table.size() * sizeof(std::uint32_t));
    return directions;
}

/// Runs the consumer for `push`; its values, [sample][oas_sample, oas_draw][dim], from `values`.
const float* runConsumer(oas::vk::Context& ctx, oas::vk::ComputePipeline& pipe, const Push& push, oas::vk::Buffer& values,
                         oas::vk::Buffer& directions)
{
    std::memset(values.data(), 0, values.size());
    oas::vk::Buffer* buffers[] = {&values, &directions};
    ctx.dispatch(pipe, buffers, &push, sizeof(push), (push.spp + 7) / 8);
    return static_cast<const float*>(values.data());
}

class Specialization : public oas::test::GpuTest {};

TEST_F(Specialization, AMismatchedPatternGivesNaNNeverWrongValues)
{
    oas::vk::Context& ctx = context();
    const auto list = patterns();
    oas::vk::Buffer directions = directionBuffer(ctx);
    oas::vk::Buffer values(ctx, std::size_t(kMaxSamplesChecked) * 2 * kDims * sizeof(float));
    std::size_t matched = 0, refused = 0;
    for (const auto& [specName, specPattern] : list) {
        OasSpecialization spec;
        oas_specialization(&specPattern, &spec);
        oas::vk::ComputePipeline pipe(ctx, specialized_consumer_spv, sizeof(specialized_consumer_spv), 2, sizeof(Push),
                                      constantsFor(specPattern));
        for (const auto& [name, pattern] : list) {
            SCOPED_TRACE("shader specialized for " + specName + ", given " + name);
            const bool matches = oas_specialization_matches(&pattern, &spec) != 0;
            const Push push{pattern, std::min(pattern.N, kMaxSamplesChecked), kDims, kPixelSeed, 0};
            const float* got = runConsumer(ctx, pipe, push, values, directions);
            std::size_t wrong = 0;
            for (std::uint32_t i = 0; i < push.spp; ++i)
                for (std::uint32_t way = 0; way < 2; ++way)
                    for (std::uint32_t d = 0; d < kDims; ++d) {
                        const float v = got[(i * 2 + way) * kDims + d];
                        if (matches) {
                            const float expected = oas::sample(pattern, kPixelSeed, i, d);
                            wrong += std::memcmp(&v, &expected, sizeof v) != 0;
                        } else {
                            wrong += !std::isnan(v);
                        }
                    }
            EXPECT_EQ(wrong, 0u) << (matches ? "values differing from oas::sample" : "values that are not NaN");
            (matches ? matched : refused) += 1;
        }
    }
    // Each pattern matches its own specialization, and the list holds both verdicts: a large-N
    // specialization (smallN 0) takes the small Bose patterns of its kind too.
    EXPECT_GE(matched, list.size() + 1);
    EXPECT_GT(refused, list.size());
}

TEST_F(Specialization, ADrawWithinItsPromisedBlocksIsExactAndOnePastThemIsNaN)
{
    // OAS_STATIC_DRAW_BLOCKS 2 promises that a draw spans at most two OA blocks. Draws of 6
    // dimensions starting at every first dimension in [0, 20): they span (first + 5) / B - first / B
    // + 1 blocks of B columns; within two, every value is oas::sample's bit for bit; past two
    // (blocks of 3 or 4 columns), every value is NaN. Baselines have no blocks: always exact.
    oas::vk::Context& ctx = context();
    oas::vk::Buffer directions = directionBuffer(ctx);
    oas::vk::Buffer values(ctx, std::size_t(kMaxSamplesChecked) * 2 * kDims * sizeof(float));
    const std::pair<const char*, oas::Pattern> list[] = {
        {"bose 49 (8 columns)", make("bose", 49)},           {"bose 64 (9)", make("bose", 64)},
        {"bose 9 (4)", make("bose", 9)},                     {"bush 27 t=3 (4)", make("bush", 27, "cmj", 3)},
        {"addelman-kempthorne 18 (7)", make("addelman-kempthorne", 18)}, {"cmjnd 27 d=3 (3)", make("cmjnd", 27, "cmj", 3)},
        {"random 16", make("random", 16)},                   {"cmj2d 16", make("cmj2d", 16)}};
    std::size_t exact = 0, refused = 0;
    for (const auto& [name, pattern] : list) {
        oas::vk::ComputePipeline pipe(ctx, specialized_consumer_two_blocks_spv, sizeof(specialized_consumer_two_blocks_spv), 2,
                                      sizeof(Push), constantsFor(pattern));
        const bool baseline = !oas::isOrthogonalArray(oas_construction_name(pattern.construction));
        for (std::uint32_t first = 0; first < 20; ++first) {
            SCOPED_TRACE(std::string(name) + ", first dimension " + std::to_string(first));
            const std::uint32_t b = pattern.blockDims;
            const bool within = baseline || (first + kDims - 1) / b - first / b + 1 <= 2;
            const Push push{pattern, std::min(pattern.N, kMaxSamplesChecked), kDims, kPixelSeed, first};
            const float* got = runConsumer(ctx, pipe, push, values, directions);
            std::size_t wrong = 0;
            for (std::uint32_t i = 0; i < push.spp; ++i)
                for (std::uint32_t d = 0; d < kDims; ++d) {
                    const float viaSample = got[(i * 2) * kDims + d], viaDraw = got[(i * 2 + 1) * kDims + d];
                    const float expected = oas::sample(pattern, kPixelSeed, i, first + d);
                    wrong += std::memcmp(&viaSample, &expected, sizeof expected) != 0;  // oas_sample is never affected
                    wrong += within ? std::memcmp(&viaDraw, &expected, sizeof expected) != 0 : !std::isnan(viaDraw);
                }
            EXPECT_EQ(wrong, 0u) << (within ? "draw values differing from oas::sample" : "draw values that are not NaN");
            (within ? exact : refused) += 1;
        }
    }
    // Both verdicts occur: blocks of 3 and 4 columns are spanned three at a time by 6 dimensions.
    EXPECT_GT(exact, 100u);
    EXPECT_GT(refused, 10u);
}

TEST(SpecializationC, FieldKindDegreeAndSizeFollowTheConstruction)
{
    // From the constructions' mathematics: Bose q^2 works over GF(q), Bush q^t over GF(q),
    // Bose-Bush 2q^2 (q = 2^k) over GF(2q) (Bose and Bush 1952: its levels are GF(2q)'s elements
    // folded in pairs), Addelman-Kempthorne 2q^2 over GF(q), q odd; CMJND and the baselines have
    // no field (kind 0, degree 1).
    struct Expected {
        const char* sampler;
        std::uint32_t spp, strength, kind, degree, smallN, indexBits;
    };
    const Expected cases[] = {
        // indexBits: 24 (any N) but for Halton, where it is the bits of N - 1: 15 = 0b1111 has
        // 4, 16 = 0b10000 has 5, 0 has none.
        {"bose", 49, 0, 0, 1, 1, 24},      {"bose", 64, 0, 1, 3, 1, 24},  {"bose", 81, 0, 2, 2, 1, 24},
        {"bose", 66049, 0, 0, 1, 0, 24},   {"bush", 512, 3, 1, 3, 1, 24}, {"bose-bush", 32, 0, 1, 3, 1, 24},
        {"addelman-kempthorne", 162, 0, 2, 2, 1, 24}, {"cmjnd", 27, 3, 0, 1, 1, 24}, {"halton", 16, 0, 0, 1, 1, 4},
        {"halton", 17, 0, 0, 1, 1, 5},     {"halton", 1, 0, 0, 1, 1, 0},  {"halton", 100000, 0, 0, 1, 0, 17},
        {"sobol", 100000, 0, 0, 1, 0, 24},
        // faure: its field GF(q), q the smallest prime power >= d, and indexBits K, the base-q
        // digits of N = q^K >= spp: 100 -> 11^2, 81 -> 9^2, 10 -> 4^2 over GF(2^2), 300 -> 3^6.
        {"faure", 100, 10, 0, 1, 1, 2},    {"faure", 81, 9, 2, 2, 1, 2},  {"faure", 10, 4, 1, 2, 1, 2},
        {"faure", 300, 3, 0, 1, 1, 6},
    };
    for (const auto& c : cases) {
        const oas::Pattern pattern = make(c.sampler, c.spp, "mj", c.strength);
        OasSpecialization s;
        oas_specialization(&pattern, &s);
        SCOPED_TRACE(std::string(c.sampler) + " " + std::to_string(c.spp));
        EXPECT_EQ(s.construction, pattern.construction);
        EXPECT_EQ(s.offset, pattern.offset);
        EXPECT_EQ(s.fieldKind, c.kind);
        EXPECT_EQ(s.fieldDegree, c.degree);
        EXPECT_EQ(s.smallN, c.smallN);
        EXPECT_EQ(s.indexBits, c.indexBits);
        EXPECT_TRUE(oas_specialization_matches(&pattern, &s));
        OasSpecialization other = s;
        other.offset ^= 1u;
        EXPECT_FALSE(oas_specialization_matches(&pattern, &other));
        other = s;
        other.smallN = 0;  // the long division serves every N
        EXPECT_TRUE(oas_specialization_matches(&pattern, &other));
        other = s;
        other.indexBits = 24;  // any N
        EXPECT_TRUE(oas_specialization_matches(&pattern, &other));
        if (c.indexBits > 0 && c.indexBits < 24) {  // one bit fewer no longer holds N - 1 (faure: another K)
            other.indexBits = c.indexBits - 1;
            EXPECT_FALSE(oas_specialization_matches(&pattern, &other));
        }
    }
    EXPECT_EQ(sizeof(OasSpecialization), 6 * sizeof(std::uint32_t));  // VkSpecializationMapEntry offsets
}

}  // namespace
