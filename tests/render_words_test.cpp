// The path tracer's exact per-pixel sums on every shipped scene, on both devices, against a record
// of them: a refactor guard. Its reason is that nothing changed. A restructuring of the integrator
// (the path as an explicit state record stepped one vertex at a time; a wavefront of kernels over
// queues of such records) must give every scene the same words as the megakernel before it; the
// GPU-vs-CPU comparisons (RenderGpu.AgreesWithTheCpuReference) stay the independent check that the
// words are right. The GPU and the CPU twin differ in the last bits of sin, cos and sqrt, so each
// device has its own record; the GPU's names its device (lavapipe in CI), and on another the GPU
// case says SKIPPED.
//
// The record (tests/data/render_words.json) says at which commit it was made. A change that is
// meant to change images (a new effect, a fixed bug) rewrites it, and its commit says why:
//   OAS_RECORD_RENDER_WORDS=1 build/tests/render_words_test
// writes the file from this build instead of comparing (and says so in the test's output).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gpu_test_support.hpp"
#include "render/fnv1a.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"

namespace {

using namespace oas;

/// One recorded render: a scene at a small width, a sampler, samples [0, spp) of every pixel.
struct RenderCase {
    std::string scene;    ///< file name under scenes/
    std::string sampler;  ///< oas::PatternRequest::sampler
    std::uint32_t width;  ///< the height keeps the scene's aspect ratio
    std::uint32_t spp;
    std::uint32_t samplesPerDispatch;  ///< the GPU's batches (the CPU traces them all at once)

    std::string key() const
    {
        return scene + " " + sampler + " " + std::to_string(width) + "px " + std::to_string(spp) + "spp";
    }
};

/// Every shipped scene (so that a new scene must be recorded), each with an OA render over two
/// passes of its pattern, split across dispatches, and a one-sample random render.
std::vector<RenderCase> renderCases()
{
    std::vector<std::string> scenes;
    for (const auto& entry : std::filesystem::directory_iterator(OAS_SCENES_DIR))
        if (entry.path().extension() == ".json") scenes.push_back(entry.path().filename().string());
    std::sort(scenes.begin(), scenes.end());
    std::vector<RenderCase> cases;
    for (const auto& scene : scenes) {
        cases.push_back({scene, "oa", 12, 32, 13});
        cases.push_back({scene, "random", 16, 1, 1});
    }
    return cases;
}

/// FNV-1a (64-bit) over the words' bytes (little-endian on the machines we run): a short, exact
/// fingerprint of the sums.
std::string fingerprint(const std::vector<std::uint32_t>& words)
{
    render::Fnv1a f;
    f.bytes(words.data(), words.size() * sizeof(std::uint32_t));
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(f.h));
    return text;
}

struct Prepared {
    scene::Scene scene;
    render::DimensionPlan plan;
    render::SceneData data;
    Pattern pattern;
    render::SampleBatch batch;
};

Prepared prepare(const RenderCase& c)
{
    Prepared p{scene::loadScene(std::string(OAS_SCENES_DIR) + "/" + c.scene), {}, {}, {}, {}};
    p.scene.height = std::max(1u, p.scene.height * c.width / p.scene.width);
    p.scene.width = c.width;
    p.plan = render::planDimensions(p.scene);
    p.data = render::flattenScene(p.scene);
    PatternRequest request;
    request.sampler = c.sampler;
    request.spp = c.spp;
    request.dims = p.plan.sampleDims;
    p.pattern = makePattern(request);
    p.batch.width = p.scene.width;
    p.batch.height = p.scene.height;
    p.batch.count = c.spp;
    p.batch.seed = 11;
    return p;
}

const std::string kRecordPath = std::string(OAS_TEST_DATA_DIR) + "/render_words.json";

bool recording()
{
    const char* v = std::getenv("OAS_RECORD_RENDER_WORDS");
    return v && std::string(v) == "1";
}

/// The source tree's commit (and "+changes" when it has uncommitted ones), for the record.
std::string headCommit()
{
    const std::string git = "git -C \"" + std::string(OAS_SCENES_DIR) + "\" ";
    std::string commit;
    if (FILE* p = popen((git + "rev-parse --short HEAD 2>/dev/null").c_str(), "r")) {
        char line[64] = {};
        if (std::fgets(line, sizeof line, p)) commit = line;
        pclose(p);
    }
    while (!commit.empty() && (commit.back() == '\n' || commit.back() == '\r')) commit.pop_back();
    if (commit.empty()) return "unknown";
    if (std::system((git + "diff --quiet HEAD -- 2>/dev/null").c_str()) != 0) commit += "+changes";
    return commit;
}

nlohmann::json readRecord()
{
    nlohmann::json record;
    if (std::ifstream in(kRecordPath); in) record = nlohmann::json::parse(in);
    return record;
}

/// Compares this build's fingerprints for `device` with the record, or (recording) writes them
/// into the record beside the other device's. `deviceName`: the Vulkan device's name for "gpu".
void checkAgainstRecord(const std::string& device, const std::map<std::string, std::string>& fingerprints,
                        const std::string& deviceName = "")
{
    nlohmann::json record = readRecord();
    if (recording()) {
        record["why"] = "A refactor guard: the exact sums of every shipped scene before a change that must not change them.";
        record["rewrite"] = "OAS_RECORD_RENDER_WORDS=1 build/tests/render_words_test";
        record[device] = fingerprints;
        if (!deviceName.empty()) record[device + "_device"] = deviceName;
        record["recorded_at"] = headCommit();
        const std::string temporary = kRecordPath + ".tmp";
        std::ofstream(temporary) << record.dump(2) << "\n";
        std::filesystem::rename(temporary, kRecordPath);
        std::printf("RECORDED (not compared): %zu %s renders into %s\n", fingerprints.size(), device.c_str(),
                    kRecordPath.c_str());
        return;
    }
    ASSERT_TRUE(record.contains(device)) << kRecordPath << " has no " << device << " renders";
    const auto& recorded = record[device];
    for (const auto& [key, value] : fingerprints) {
        ASSERT_TRUE(recorded.contains(key)) << device << " render \"" << key << "\" is not in " << kRecordPath
                                            << " (a new scene? record it: " << record.value("rewrite", "") << ")";
        EXPECT_EQ(recorded[key].get<std::string>(), value)
            << device << " render \"" << key << "\": its sums are not the recorded ones. If the change was meant to "
            << "change images, rewrite the record and say why in the commit; if not, it changed the tracer's results";
    }
    EXPECT_EQ(recorded.size(), fingerprints.size()) << kRecordPath << " records renders this test no longer makes";
}

/// The render's words are not all zero (a black image would make the guard vacuous for it).
void expectLight(const render::Accumulation& a, const std::string& what)
{
    double total = 0;
    for (std::size_t i = 0; i < a.pixelCount(); ++i) total += render::meanValue(a.pixel(i), 0);
    EXPECT_GT(total, 0.0) << what << " renders black: its fingerprint would guard nothing";
}

TEST(RenderWords, TheCpuTwinsSumsAreTheRecordedOnes)
{
    std::map<std::string, std::string> fingerprints;
    for (const auto& c : renderCases()) {
        auto p = prepare(c);
        render::Accumulation sums(p.scene.width, p.scene.height);
        render::traceCpu(p.data, p.plan, p.pattern, p.batch, sums);
        expectLight(sums, c.key());
        fingerprints[c.key()] = fingerprint(sums.words);
    }
    checkAgainstRecord("cpu", fingerprints);
}

class RenderWordsGpu : public test::GpuTest {};

/// The GPU's fingerprints of every case, rendered with `kernel`.
std::map<std::string, std::string> gpuFingerprints(vk::Context& context, render::GpuTracerOptions::Kernel kernel)
{
    std::map<std::string, std::string> fingerprints;
    for (const auto& c : renderCases()) {
        auto p = prepare(c);
        render::GpuTracerOptions options;
        options.kernel = kernel;
        render::GpuTracer gpu(context, p.data, p.plan, p.pattern, options);
        for (std::uint32_t first = 0; first < c.spp; first += c.samplesPerDispatch) {
            p.batch.firstSample = first;
            p.batch.count = std::min(c.samplesPerDispatch, c.spp - first);
            gpu.trace(p.batch);
        }
        const auto sums = gpu.accumulation();
        expectLight(sums, c.key());
        fingerprints[c.key()] = fingerprint(sums.words);
    }
    return fingerprints;
}

/// The record's GPU words are of another device than this one: nothing to compare with.
bool recordIsOfAnotherGpu(const nlohmann::json& record, const vk::Context& context)
{
    return record.value("gpu_device", "") != context.deviceName();
}

TEST_F(RenderWordsGpu, TheGpusSumsAreTheRecordedOnes)
{
    // The record holds one device's words (another driver's sin, cos and sqrt differ in their last
    // bits): on another device there is nothing to compare with, and the test says so.
    const auto record = readRecord();
    if (!recording() && recordIsOfAnotherGpu(record, context()))
        GTEST_SKIP() << "SKIPPED: " << kRecordPath << " holds the GPU words of \"" << record.value("gpu_device", "")
                     << "\", not of this device (\"" << context().deviceName() << "\"); record them with "
                     << record.value("rewrite", "");
    checkAgainstRecord("gpu", gpuFingerprints(context(), render::GpuTracerOptions::Kernel::Mega), context().deviceName());
}

TEST_F(RenderWordsGpu, TheWavefrontsSumsAreTheMegakernelsRecordedOnes)
{
    // The wavefront (pt_wavefront.comp) runs the megakernel's integrator one step per dispatch over
    // queues of path records; the sums are integers, so every scene's words must be the
    // megakernel's, which the record holds (recorded from the megakernel only, before the wavefront
    // existed: a record the wavefront never wrote).
    const auto record = readRecord();
    if (recording()) GTEST_SKIP() << "SKIPPED: recording: the megakernel writes the record, the wavefront is compared with it";
    if (recordIsOfAnotherGpu(record, context()))
        GTEST_SKIP() << "SKIPPED: " << kRecordPath << " holds the GPU words of \"" << record.value("gpu_device", "")
                     << "\", not of this device (\"" << context().deviceName() << "\")";
    checkAgainstRecord("gpu", gpuFingerprints(context(), render::GpuTracerOptions::Kernel::Wavefront), context().deviceName());
}

}  // namespace
