// Exact sums, render files and oas-merge: a frame split into sample-range shards, rendered in any
// order and merged, equals the one-process render bit for bit, on the GPU and on the CPU; shards
// that do not belong together are refused, naming the file and the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <csignal>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "gpu_test_support.hpp"
#include "image/image.hpp"
#include "oas/pattern.hpp"
#include "render/accumulation.hpp"
#include "render/render_file.hpp"
#include "render/tracer.hpp"

namespace fs = std::filesystem;
using oas::render::Accumulation;
using Words = std::array<std::uint32_t, 3>;  // lo, mid, hi
using u128 = unsigned __int128;

namespace {

/// floor(v * 2^32) for a finite v >= 0, from v's own mantissa and exponent (frexp), without the
/// float steps pt_sum_of takes: the independent reference.
u128 fixedReference(float v)
{
    if (v == 0.0f) return 0;
    int e = 0;
    const float m = std::frexp(v, &e);                      // v = m * 2^e, m in [0.5, 1)
    const auto mantissa = u128(std::ldexp(double(m), 24));  // 24-bit integer: v = mantissa * 2^(e - 24)
    const int shift = e - 24 + 32;                          // v * 2^32 = mantissa * 2^shift
    if (shift <= -128) return 0;                            // (a shift by the width or more is undefined)
    return shift >= 0 ? mantissa << shift : mantissa >> -shift;
}

Words wordsOf(u128 x)
{
    return {std::uint32_t(x), std::uint32_t(x >> 32), std::uint32_t(x >> 64)};
}

/// Channel 0 of a PtSum as words.
Words redWords(const oas::pt::PtSum& s)
{
    return {s.lo.x, s.mid.x, s.hi.x};
}

/// Radiances over the whole summable range: tiny, ordinary, fireflies, up to just below 2^64.
std::vector<float> wideRadiances(std::size_t n, std::uint32_t seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> mantissa(0.5f, 1.0f);
    std::uniform_int_distribution<int> exponent(-40, 64);
    std::vector<float> v(n);
    for (float& x : v) x = std::ldexp(mantissa(rng), exponent(rng));  // < 2^64
    return v;
}

}  // namespace

TEST(ExactSum, WordsAreTheRadianceTimes2To32RoundedDown)
{
    std::vector<float> values = wideRadiances(200000, 1);
    const float justBelow = std::nextafter(18446744073709551616.0f, 0.0f);
    for (float v : {0.0f, -0.0f, 1.0f, 0.5f, 3.0f, 1e-10f, 2.3283064e-10f, 1e-45f, 4294967295.0f, 4294967296.0f, justBelow,
                    std::numeric_limits<float>::min()})
        values.push_back(v);
    for (float v : values) {
        ASSERT_TRUE(oas::pt::pt_summable(glm::vec3(v))) << v;
        ASSERT_EQ(redWords(oas::pt::pt_sum_of(glm::vec3(v))), wordsOf(fixedReference(v))) << v;
    }
    // The largest summable value: its 24 mantissa bits at the top of the 96-bit number.
    EXPECT_EQ(redWords(oas::pt::pt_sum_of(glm::vec3(justBelow))), (Words{0u, 0u, 0xffffff00u}));
}

TEST(ExactSum, OnlyValuesFrom0ToBelow2To64AreSummable)
{
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (float bad : {nan, inf, -inf, -1.0f, -1e-30f, 18446744073709551616.0f, 1e30f})
        EXPECT_FALSE(oas::pt::pt_summable(glm::vec3(1.0f, bad, 1.0f))) << bad;
    EXPECT_TRUE(oas::pt::pt_summable(glm::vec3(0.0f, -0.0f, 1e19f)));
}

TEST(ExactSum, AnySplitAndOrderGivesTheExactSum)
{
    // 4096 samples of one pixel over the whole range, summed one by one, and as shards of random
    // sizes (one sample up to hundreds) added in a shuffled order: the same words, and the words
    // of the exact sum of the references (computed in 128-bit integers).
    const std::vector<float> values = wideRadiances(4096, 2);
    u128 exact = 0;
    Accumulation sequential(1, 1);
    for (float v : values) {
        exact += fixedReference(v);
        const auto s = oas::pt::pt_sum_of(glm::vec3(v, 0.0f, v));
        sequential.addToPixel(0, s.lo, s.mid, s.hi, 1, 0);
    }
    const std::uint32_t* p = sequential.pixel(0);
    EXPECT_EQ((Words{p[0], p[1], p[2]}), wordsOf(exact));
    EXPECT_EQ((Words{p[6], p[7], p[8]}), wordsOf(exact));
    EXPECT_EQ((Words{p[3], p[4], p[5]}), (Words{0, 0, 0}));

    std::mt19937 rng(3);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<Accumulation> shards;
        for (std::size_t i = 0; i < values.size();) {
            const std::size_t n = std::min<std::size_t>(values.size() - i, 1 + rng() % (trial < 10 ? 3 : 400));
            Accumulation shard(1, 1);
            for (std::size_t k = i; k < i + n; ++k) {
                const auto s = oas::pt::pt_sum_of(glm::vec3(values[k], 0.0f, values[k]));
                shard.addToPixel(0, s.lo, s.mid, s.hi, 1, 0);
            }
            shards.push_back(shard);
            i += n;
        }
        std::shuffle(shards.begin(), shards.end(), rng);
        Accumulation merged(1, 1);
        for (const Accumulation& shard : shards) merged.add(shard);
        ASSERT_EQ(merged.words, sequential.words) << "trial " << trial << ", " << shards.size() << " shards";
    }
}

TEST(ExactSum, TheMeanIsTheSumOverTheCountRoundedOnce)
{
    Accumulation a(1, 1);
    for (float v : {0.5f, 0.25f, 2.0f, 1e18f}) {
        const auto s = oas::pt::pt_sum_of(glm::vec3(v, 1.0f, 0.0f));
        a.addToPixel(0, s.lo, s.mid, s.hi, 1, 0);
    }
    a.addToPixel(0, {}, {}, {}, 1, 1);  // a rejected sample: counted, not summed
    EXPECT_EQ(a.samples(0), 5u);
    EXPECT_EQ(a.rejected(0), 1u);
    const auto image = a.image();
    EXPECT_EQ(image.rgba[0], float((2.75 + 1e18) / 5.0));
    EXPECT_EQ(image.rgba[1], 0.8f);
    EXPECT_EQ(image.rgba[2], 0.0f);
    EXPECT_EQ(image.rgba[3], 1.0f);
    EXPECT_EQ(Accumulation(1, 1).image().rgba[0], 0.0f) << "no samples: black";
}

TEST(ExactSum, AddingRefusesCountsPast2To32)
{
    Accumulation a(2, 1), b(2, 1);
    a.addToPixel(1, {}, {}, {}, 0xffffffffu, 0);
    b.addToPixel(1, {}, {}, {}, 1, 0);
    EXPECT_THROW(a.add(b), std::overflow_error);
    EXPECT_EQ(a.samples(1), 0xffffffffu) << "nothing added";
    EXPECT_THROW(a.add(Accumulation(1, 2)), std::invalid_argument);
}

// ---- Render files and merges (library level) -------------------------------------------------

namespace {

fs::path scratchDir(const std::string& name)
{
    const fs::path dir = fs::temp_directory_path() / ("oas_merge_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

/// A 3x2 render file holding `range`, with `value` per sample in every pixel.
oas::render::RenderFile fakeShard(oas::render::SampleRange range, float value = 0.5f)
{
    oas::render::RenderFile f;
    f.sums = Accumulation(3, 2);
    const auto s = oas::pt::pt_sum_of(glm::vec3(value));
    for (std::size_t i = 0; i < 6; ++i)
        for (std::uint32_t k = range.first; k < range.end; ++k) f.sums.addToPixel(i, s.lo, s.mid, s.hi, 1, 0);
    f.ranges = {range};
    f.attributes = {{"oas.format", oas::render::kRenderFormat},
                    {"oas.sceneHash", "0123456789abcdef"},
                    {"oas.resolution", "3x2"},
                    {"oas.sampler", "bose q=4"},
                    {"oas.pattern", "00000001"},
                    {"oas.dimensionPlan", "7D"},
                    {"oas.seed", "0"},
                    {"oas.device", "cpu"},
                    {"oas.renderTimeSeconds", "1.5"}};
    return f;
}

/// The sums as the UINT channels of the file format (render/render_file.hpp: words in order).
oas::image::UintChannels sumChannels(const Accumulation& sums)
{
    const char* names[] = {"sum.R0", "sum.R1", "sum.R2", "sum.G0",      "sum.G1",      "sum.G2",
                           "sum.B0", "sum.B1", "sum.B2", "sum.samples", "sum.rejected"};
    oas::image::UintChannels channels;
    for (std::size_t k = 0; k < 11; ++k)
        for (std::size_t i = 0; i < sums.pixelCount(); ++i) channels[names[k]].push_back(sums.pixel(i)[k]);
    return channels;
}

template <class F>
std::string errorOf(F&& f)
{
    try {
        f();
    } catch (const oas::InvalidArgument& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST(RenderFile, WritesAndReadsTheSumsAndRangesBitForBit)
{
    const fs::path dir = scratchDir("roundtrip");
    auto shard = fakeShard({3, 11}, 1e10f);
    shard.sums.addToPixel(4, {1, 2, 3}, {4, 5, 6}, {7, 8, 9}, 0, 0);
    oas::render::writeRenderFile((dir / "a.exr").string(), shard.sums, shard.ranges, shard.attributes);
    const auto back = oas::render::readRenderFile((dir / "a.exr").string());
    EXPECT_EQ(back.sums.words, shard.sums.words);
    EXPECT_EQ(back.ranges, shard.ranges);
    EXPECT_EQ(back.attributes.at("oas.samples"), "3:11");
    EXPECT_EQ(back.attributes.at("oas.spp"), "8");
    EXPECT_EQ(back.attributes.at("oas.seed"), "0");
    fs::remove_all(dir);
}

TEST(RenderFile, MergeRefusesShardsOfAnotherFrameNamingFileAndField)
{
    for (const std::string& field : oas::render::frameFields()) {
        auto a = fakeShard({0, 4}), b = fakeShard({4, 8});
        b.attributes[field] += "x";
        const std::string error = errorOf([&] { oas::render::mergeRenders({a, b}, {"a.exr", "b.exr"}); });
        EXPECT_NE(error.find("b.exr: header field " + field), std::string::npos) << error;
        EXPECT_NE(error.find("a.exr"), std::string::npos) << error;
    }
    const std::string overlap = errorOf([&] {
        oas::render::mergeRenders({fakeShard({0, 5}), fakeShard({4, 8})}, {"a.exr", "b.exr"});
    });
    EXPECT_NE(overlap.find("samples 4:8 overlap samples 0:5 of a.exr"), std::string::npos) << overlap;
}

TEST(RenderFile, MergeAddsSumsJoinsRangesAndTimes)
{
    const auto merged = oas::render::mergeRenders({fakeShard({8, 9}), fakeShard({0, 4}), fakeShard({4, 8})}, {"a", "b", "c"});
    EXPECT_EQ(oas::render::formatRanges(merged.ranges), "0:9");
    EXPECT_EQ(merged.sums.words, fakeShard({0, 9}).sums.words);
    EXPECT_EQ(merged.attributes.at("oas.spp"), "9");
    EXPECT_EQ(merged.attributes.at("oas.shards"), "3");
    EXPECT_EQ(std::stod(merged.attributes.at("oas.renderTimeSeconds")), 4.5);
    const auto gap = oas::render::mergeRenders({fakeShard({0, 2}), fakeShard({5, 7})}, {"a", "b"});
    EXPECT_EQ(oas::render::formatRanges(gap.ranges), "0:2,5:7");
}

TEST(RenderFile, ReadRefusesWhatIsNotACompleteRenderFile)
{
    const fs::path dir = scratchDir("refuse");
    const auto shard = fakeShard({0, 4});
    const std::string good = (dir / "good.exr").string();
    oas::render::writeRenderFile(good, shard.sums, shard.ranges, shard.attributes);
    // A plain EXR (oas-diff's input, any other program's output).
    const std::string plain = (dir / "plain.exr").string();
    oas::image::writeExr(plain, oas::image::Image(3, 2, 1, 1, 1), {{"oas.spp", "4"}});
    EXPECT_NE(errorOf([&] { oas::render::readRenderFile(plain); }).find("plain.exr: header field oas.format is missing"),
              std::string::npos);
    // The header of a render file without its sums.
    auto attributes = shard.attributes;
    attributes["oas.samples"] = "0:4";
    oas::image::writeExr((dir / "nosums.exr").string(), shard.sums.image(), attributes);
    EXPECT_NE(errorOf([&] { oas::render::readRenderFile((dir / "nosums.exr").string()); }).find("channel sum.R0 is missing"),
              std::string::npos);
    // Truncated at every 97th byte: always an error naming the file, never a crash.
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    for (std::size_t size = 0; size < bytes.size(); size += 97) {
        const std::string cut = (dir / "cut.exr").string();
        std::ofstream(cut, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(size));
        EXPECT_NE(errorOf([&] { oas::render::readRenderFile(cut); }).find("cut.exr"), std::string::npos) << size;
    }
    // Sums that disagree with the header's ranges.
    EXPECT_THROW(oas::render::writeRenderFile((dir / "lie.exr").string(), shard.sums, {{0, 5}}, shard.attributes),
                 std::logic_error);
    fs::remove_all(dir);
}

// ---- oas-render --samples and oas-merge, end to end ------------------------------------------

namespace {

/// Runs a command line; returns its exit status, its output in `output`.
int run(const std::string& command, std::string* output = nullptr)
{
    const std::string log = (fs::temp_directory_path() / ("oas_merge_log_" + std::to_string(::getpid()))).string();
    const int status = std::system((command + " >" + log + " 2>&1").c_str());
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (output) *output = text;
    fs::remove(log);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string fileBytes(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// cornell7d (lens, motion blur, area light: 7 dimensions) at 40x30 and 16 spp, written beside
/// the shards; `albedoScale` != 1 makes another scene of the same size.
std::string smallScene(const fs::path& dir, float albedoScale = 1.0f)
{
    std::ifstream in(std::string(OAS_SCENES_DIR) + "/cornell7d.json");
    nlohmann::json scene = nlohmann::json::parse(in);
    scene["resolution"] = {40, 30};
    scene["sampler"]["spp"] = 16;
    for (auto& a : scene["materials"][0]["albedo"]) a = a.get<double>() * albedoScale;
    const fs::path path = dir / (albedoScale == 1.0f ? "scene.json" : "other_scene.json");
    std::ofstream(path) << scene.dump(2);
    return path.string();
}

/// The frame in one process, then in shards that are uneven, include a one-sample shard, cut
/// passes (the GPU tracer takes 8 samples per pass here; the CPU one up to kCpuSamplesPerBatch, so
/// there the shards cut its one pass) and are merged out of order: the same pixels and sums, bit
/// for bit, and the same PNG bytes.
void expectShardsMergeExactly(const std::string& device)
{
    const fs::path dir = scratchDir("cli_" + device);
    const std::string scene = smallScene(dir), render = std::string(OAS_RENDER_EXE) + " " + scene + " --device " + device;
    const std::string whole = (dir / "whole.exr").string();
    std::string log;
    ASSERT_EQ(run(render + " -o " + whole, &log), 0) << log;
    std::vector<std::string> shards;
    for (const char* range : {"13:16", "0:5", "6:13", "5:6"}) {
        std::string name = std::string("shard_") + range + ".exr";
        name[name.find(':')] = '_';
        shards.push_back((dir / name).string());
        ASSERT_EQ(run(render + " --samples " + range + " -o " + shards.back(), &log), 0) << log;
    }
    const std::string merged = (dir / "merged.exr").string();
    std::string list;
    for (const auto& s : shards) list += " " + s;
    ASSERT_EQ(run(std::string(OAS_MERGE_EXE) + list + " --expect 0:16 -o " + merged, &log), 0) << log;
    EXPECT_NE(log.find("samples 0:16 of 16"), std::string::npos) << log;
    ASSERT_EQ(run(std::string(OAS_DIFF_EXE) + " --exact " + merged + " " + whole, &log), 0) << log;
    EXPECT_EQ(fileBytes(dir / "merged.png"), fileBytes(dir / "whole.png"));
    const auto a = oas::render::readRenderFile(merged), b = oas::render::readRenderFile(whole);
    EXPECT_EQ(a.sums.words, b.sums.words);
    EXPECT_EQ(a.attributes.at("oas.samples"), "0:16");
    EXPECT_EQ(a.attributes.at("oas.shards"), "4");
    // A merge of merges is the same frame again.
    const std::string first = (dir / "first.exr").string(), second = (dir / "second.exr").string(),
                      again = (dir / "again.exr").string();
    ASSERT_EQ(run(std::string(OAS_MERGE_EXE) + " " + shards[1] + " " + shards[3] + " -o " + first, &log), 0) << log;
    ASSERT_EQ(run(std::string(OAS_MERGE_EXE) + " " + shards[0] + " " + shards[2] + " -o " + second, &log), 0) << log;
    ASSERT_EQ(run(std::string(OAS_MERGE_EXE) + " " + second + " " + first + " -o " + again, &log), 0) << log;
    EXPECT_EQ(run(std::string(OAS_DIFF_EXE) + " --exact " + again + " " + whole, &log), 0) << log;
    fs::remove_all(dir);
}

}  // namespace

TEST(MergeCli, ShardsEqualTheWholeRenderOnTheCpu)
{
    expectShardsMergeExactly("cpu");
}

class MergeGpu : public oas::test::GpuTest {};
TEST_F(MergeGpu, ShardsEqualTheWholeRenderOnTheGpu)
{
    expectShardsMergeExactly("gpu");
}

TEST(MergeCli, RefusesShardsThatDoNotMakeOneFrameAndWritesNothing)
{
    const fs::path dir = scratchDir("cli_refuse");
    const std::string scene = smallScene(dir), other = smallScene(dir, 0.5f);
    const std::string render = std::string(OAS_RENDER_EXE) + " --device cpu ";
    const auto shard = [&](const std::string& name, const std::string& args) {
        std::string log;
        EXPECT_EQ(run(render + args + " -o " + (dir / name).string(), &log), 0) << log;
        return (dir / name).string();
    };
    const std::string a = shard("a.exr", scene + " --samples 0:8"), b = shard("b.exr", scene + " --samples 8:16");
    struct Case {
        std::string what, second, options, expected;
    };
    const std::string plain = (dir / "plain.exr").string();
    oas::image::writeExr(plain, oas::image::Image(40, 30, 1, 1, 1), {});
    const std::string cut = (dir / "cut.exr").string();
    const std::string bBytes = fileBytes(b);
    std::ofstream(cut, std::ios::binary).write(bBytes.data(), std::streamsize(bBytes.size() / 2));
    const std::vector<Case> cases = {
        {"another seed", shard("seed.exr", scene + " --samples 8:16 --seed 7"), "", "header field oas.seed"},
        {"another scene", shard("scene.exr", other + " --samples 8:16"), "", "header field oas.sceneHash"},
        {"another sampler", shard("sampler.exr", scene + " --samples 8:16 --sampler random"), "", "header field oas.sampler"},
        {"overlapping samples", shard("overlap.exr", scene + " --samples 7:9"), "", "overlap"},
        {"a gap", shard("gap.exr", scene + " --samples 9:16"), " --expect 0:16", "hold samples 0:8,9:16, not exactly 0:16"},
        {"a truncated EXR", cut, "", "cut.exr"},
        {"a plain EXR", plain, "", "plain.exr: header field oas.format is missing"},
    };
    for (const Case& c : cases) {
        const fs::path out = dir / "out.exr";
        std::string log;
        EXPECT_EQ(run(std::string(OAS_MERGE_EXE) + " " + a + " " + c.second + c.options + " -o " + out.string(), &log), 2)
            << c.what << ": " << log;
        EXPECT_NE(log.find(c.expected), std::string::npos) << c.what << ": " << log;
        EXPECT_FALSE(fs::exists(out)) << c.what;
        EXPECT_FALSE(fs::exists(dir / "out.png")) << c.what;
    }
    // Bad ranges are refused before rendering, naming the option and the valid range.
    for (const char* bad : {"5:5", "9:3", "0:17", "a:b", "3", "-1:4", "1:2:3"}) {
        std::string log;
        EXPECT_EQ(run(render + scene + " --samples " + bad + " -o " + (dir / "bad.exr").string(), &log), 2) << bad;
        EXPECT_NE(log.find("0 <= A < B <= 16"), std::string::npos) << bad << ": " << log;
    }
    // Without --expect a gap is allowed and reported.
    std::string log;
    EXPECT_EQ(
        run(std::string(OAS_MERGE_EXE) + " " + a + " " + (dir / "gap.exr").string() + " -o " + (dir / "partial.exr").string(),
            &log),
        0)
        << log;
    EXPECT_NE(log.find("samples 0:8,9:16 of 16"), std::string::npos) << log;
    fs::remove_all(dir);
}

TEST(RenderFile, SampleRangeParsingTakesOnlyWellFormedRangesAndNeverCrashes)
{
    EXPECT_EQ(oas::render::parseSampleRange("0:16", 16, "--samples"), (oas::render::SampleRange{0, 16}));
    EXPECT_EQ(oas::render::parseSampleRange("15:16", 16, "--samples"), (oas::render::SampleRange{15, 16}));
    for (const char* bad : {"", ":", "0:", ":4", "4:4", "5:4", "0:17", " 0:4", "0:4 ", "+1:4", "0x1:4", "1:2:3", "0,4",
                            "99999999999:4", "0:99999999999", "-0:4"})
        EXPECT_THROW(oas::render::parseSampleRange(bad, 16, "--samples"), oas::InvalidArgument) << bad;
    // Random strings over the characters a range uses, as --samples and as a file's oas.samples:
    // either a valid range list or InvalidArgument, never another exception.
    const fs::path dir = scratchDir("fuzz");
    auto shard = fakeShard({0, 4});
    std::mt19937 rng(5);
    const std::string alphabet = "0123456789:,-+ x";
    for (int i = 0; i < 3000; ++i) {
        std::string text(rng() % 10, ' ');
        for (char& c : text) c = alphabet[rng() % alphabet.size()];
        try {
            const auto r = oas::render::parseSampleRange(text, 1000, "--samples");
            EXPECT_LT(r.first, r.end) << text;
            EXPECT_LE(r.end, 1000u) << text;
        } catch (const oas::InvalidArgument&) {
        }
        if (i % 10 == 0) {  // through a file (slower): the header field is checked against the sums too
            shard.attributes["oas.samples"] = i % 20 == 0 ? text : "0:" + text;
            const std::string path = (dir / "f.exr").string();
            oas::image::writeExr(path, shard.sums.image(), shard.attributes, sumChannels(shard.sums));
            try {
                const auto back = oas::render::readRenderFile(path);
                EXPECT_EQ(back.attributes.at("oas.samples"), "0:4") << "the sums hold 4 samples";
            } catch (const oas::InvalidArgument&) {
            }
        }
    }
    fs::remove_all(dir);
}

TEST(MergeCli, AnInterruptedRenderIsAShardThatTheRestCompletes)
{
    // SIGTERM once the first pass is reported (oas-render prints a progress line after every
    // pass when stderr is not a terminal): the render stops after the pass it is in and writes
    // what it finished as a shard. Rendering the rest with the --samples range it prints, and
    // merging, gives the uninterrupted render bit for bit: no work is lost.
    const fs::path dir = scratchDir("interrupt");
    std::ifstream in(std::string(OAS_SCENES_DIR) + "/cornell7d.json");
    nlohmann::json json = nlohmann::json::parse(in);
    // Four passes of kCpuSamplesPerBatch samples (oas-render's CPU batches), ~0.1 s each here.
    const std::uint32_t spp = 4 * oas::render::kCpuSamplesPerBatch, perPass = oas::render::kCpuSamplesPerBatch;
    json["sampler"]["spp"] = spp;
    json["resolution"] = {96, 96};
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << json.dump();
    const std::string part = (dir / "part.exr").string();

    int pipeFds[2];
    ASSERT_EQ(::pipe(pipeFds), 0);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDERR_FILENO);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
    std::vector<std::string> args = {OAS_RENDER_EXE, scene, "--device", "cpu", "-o", part};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipeFds[1]);
    std::string output;
    bool signalled = false;
    char buffer[256];
    for (ssize_t n; (n = ::read(pipeFds[0], buffer, sizeof buffer)) > 0;) {
        output.append(buffer, std::size_t(n));
        if (!signalled && output.find("progress: ") != std::string::npos) {
            ::kill(pid, SIGTERM);
            signalled = true;
        }
    }
    ::close(pipeFds[0]);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(signalled) << output;
    ASSERT_TRUE(WIFEXITED(status)) << output;
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << output;

    const auto shard = oas::render::readRenderFile(part);
    ASSERT_EQ(shard.ranges.size(), 1u);
    const std::uint32_t done = shard.ranges[0].end;
    EXPECT_EQ(shard.ranges[0].first, 0u);
    ASSERT_GT(done, 0u);
    ASSERT_LT(done, spp) << "the render finished before the signal: make it longer";
    EXPECT_EQ(done % perPass, 0u) << "whole passes";
    const std::string rest = "--samples " + std::to_string(done) + ":" + std::to_string(spp);
    EXPECT_NE(output.find(rest), std::string::npos) << "it says how to finish: " << output;

    std::string log;
    const std::string render = std::string(OAS_RENDER_EXE) + " " + scene + " --device cpu";
    ASSERT_EQ(run(render + " " + rest + " -o " + (dir / "rest.exr").string(), &log), 0) << log;
    ASSERT_EQ(run(render + " -o " + (dir / "whole.exr").string(), &log), 0) << log;
    ASSERT_EQ(run(std::string(OAS_MERGE_EXE) + " " + part + " " + (dir / "rest.exr").string() +
                      " --expect 0:" + std::to_string(spp) + " -o " + (dir / "merged.exr").string(),
                  &log),
              0)
        << log;
    EXPECT_EQ(
        run(std::string(OAS_DIFF_EXE) + " --exact " + (dir / "merged.exr").string() + " " + (dir / "whole.exr").string(), &log),
        0)
        << log;
    fs::remove_all(dir);
}
