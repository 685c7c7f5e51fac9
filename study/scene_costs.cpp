#include "scene_costs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "oas_render_sources.h"  // generated: OAS_RENDER_SOURCES_HASH
#include "render/tracer.hpp"
#include "scene/scene.hpp"
#include "stats.hpp"
#include "tracer_cache.hpp"

namespace oas::study {

const std::vector<std::string>& sceneCostColumns()
{
    static const std::vector<std::string> columns = {"scene",  "sampler", "spp",    "seconds", "se",     "rounds",
                                                     "run_id", "machine", "device", "date",    "commit", "sources"};
    return columns;
}

void writeSceneCosts(const std::string& path, const std::vector<SceneCost>& costs)
{
    CsvTable csv(sceneCostColumns());
    for (const auto& c : costs)
        csv.add({c.scene, c.sampler, std::to_string(c.spp), fmtG(c.seconds), fmtG(c.se), std::to_string(c.rounds), c.runId,
                 c.machine, c.device, c.date, c.commit, c.sources});
    csv.write(path);
}

std::vector<SceneCost> readSceneCosts(const std::string& path)
{
    const CsvRows t = readCsv(path);
    // Files from before cost runs were stamped have no commit and sources columns.
    const bool hasStamps = std::find(t.header.begin(), t.header.end(), "sources") != t.header.end();
    std::vector<SceneCost> out;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const auto& row = t.rows[i];
        auto text = [&](const char* name) { return row[t.column(name, path)]; };
        auto seconds = [&](const char* name) {
            const double v = csvNumber(t, row, name, path, i);
            if (!std::isfinite(v) || v < 0)
                throw std::runtime_error(path + ": row " + std::to_string(i + 1) + ", column \"" + name +
                                         "\": valid a finite number of seconds >= 0");
            return v;
        };
        SceneCost c;
        c.scene = text("scene");
        c.sampler = text("sampler");
        c.spp = csvCount(t, row, "spp", path, i);
        c.seconds = seconds("seconds");
        c.se = seconds("se");
        c.rounds = csvCount(t, row, "rounds", path, i);
        c.runId = text("run_id");
        c.machine = text("machine");
        c.device = text("device");
        c.date = text("date");
        if (hasStamps) {
            c.commit = text("commit");
            c.sources = text("sources");
        }
        out.push_back(c);
    }
    return out;
}

CostDevice costDeviceOf(const SceneCost& row)
{
    return row.device == kCpuTwinDeviceName ? CostDevice::CpuTwin : CostDevice::Gpu;
}

const char* costDeviceLabel(CostDevice device) { return device == CostDevice::CpuTwin ? "CPU twin" : "GPU"; }

std::vector<SceneCost> mergeSceneCosts(const std::vector<SceneCost>& kept, const std::vector<SceneCost>& fresh)
{
    std::set<std::pair<std::string, CostDevice>> freshRuns;
    for (const auto& c : fresh) freshRuns.insert({c.scene, costDeviceOf(c)});
    std::vector<SceneCost> out;
    for (const auto& c : kept)
        if (!freshRuns.count({c.scene, costDeviceOf(c)})) out.push_back(c);
    out.insert(out.end(), fresh.begin(), fresh.end());
    return out;
}

double costRunSeconds(const std::vector<SceneCost>& sceneRows, const std::string& sampler, std::uint32_t spp)
{
    const SceneCost* nearest = nullptr;
    for (const auto& c : sceneRows)
        if (c.sampler == sampler && c.spp > 0 &&
            (!nearest || std::abs(std::log(double(c.spp) / spp)) < std::abs(std::log(double(nearest->spp) / spp))))
            nearest = &c;
    if (!nearest)
        throw std::runtime_error("scene_costs.csv: the cost run of scene " +
                                 (sceneRows.empty() ? std::string("(none)") : sceneRows.front().scene) +
                                 " has no row of sampler " + sampler + ": rerun --parts scene-costs for the scene");
    return nearest->spp == spp ? nearest->seconds : nearest->seconds / nearest->spp * spp;
}

std::vector<SceneCost> costsOfScene(const std::vector<SceneCost>& costs, const std::string& scene, CostDevice device)
{
    std::vector<SceneCost> out;
    for (const auto& c : costs)
        if (c.scene == scene && costDeviceOf(c) == device) {
            if (!out.empty() && c.runId != out.front().runId)
                throw std::runtime_error("scene_costs.csv: scene " + scene + " has times from runs " + out.front().runId +
                                         " and " + c.runId +
                                         ": times from different runs are not comparable; rerun the scene's cost "
                                         "part (oas-study --parts scene-costs --scene " +
                                         scene + " --cost-devices " +
                                         (device == CostDevice::CpuTwin ? "cpu" : "gpu") + ")");
            out.push_back(c);
        }
    return out;
}

std::string renderSourcesHash() { return OAS_RENDER_SOURCES_HASH; }

std::vector<std::string> staleCostScenes(const std::vector<SceneCost>& costs)
{
    std::vector<std::string> stale;
    for (const auto& c : costs)
        if (c.sources != renderSourcesHash() && std::find(stale.begin(), stale.end(), c.scene) == stale.end())
            stale.push_back(c.scene);
    return stale;
}

SceneCost summarizeTimes(const std::vector<double>& seconds)
{
    SceneCost c;
    c.rounds = std::uint32_t(seconds.size());
    if (seconds.empty()) return c;
    double sum = 0;
    for (double s : seconds) sum += s;
    c.seconds = sum / double(seconds.size());
    if (seconds.size() > 1) {
        double ss = 0;
        for (double s : seconds) ss += (s - c.seconds) * (s - c.seconds);
        c.se = std::sqrt(ss / double(seconds.size() - 1) / double(seconds.size()));
    }
    return c;
}

std::vector<SceneCost> measureSceneCosts(const SceneRecord& record, const std::vector<SceneMeasurement>& measurements,
                                         const std::vector<SamplerSpec>& samplers, const SceneCostOptions& o,
                                         oas::vk::Context* context, double* pipelineSeconds)
{
    const bool onCpu = o.device == CostDevice::CpuTwin;
    if (!onCpu && !context) throw std::invalid_argument("scene costs on the GPU need a Vulkan device");
    if (o.rounds < 3) throw std::invalid_argument("cost rounds: valid 3 or more (alternated rounds need repeats)");
    std::string file;
    for (const auto& c : studyScenes())
        if (c.file == record.name + ".json") file = c.file;
    if (file.empty()) throw std::invalid_argument("scene " + record.name + " is not a study scene");
    auto scene = oas::scene::loadScene(o.scenesDir + "/" + file);
    scene.width = record.width;
    scene.height = record.height;
    const auto plan = oas::render::planDimensions(scene);
    const auto data = oas::render::flattenScene(scene);

    struct Point {
        std::string sampler;
        std::uint32_t spp;
        oas::Pattern pattern;
        std::vector<double> times;
    };
    std::vector<Point> points;
    for (const auto& s : samplers) {
        std::set<std::uint32_t> counts;
        for (const auto& m : measurements)
            if (m.scene == record.name && m.sampler == s.label && !m.rareOnly) counts.insert(m.spp);
        for (std::uint32_t spp : counts)
            points.push_back({s.label, spp, oas::makePattern(patternRequest(s, spp, plan.sampleDims)), {}});
    }
    if (points.empty()) throw std::invalid_argument("scene " + record.name + " has no measured points to time");

    // The GPU's pipelines are all built (and warmed up) before the first round; the CPU twin has none.
    std::optional<TracerCache> cache;
    if (!onCpu) {
        cache.emplace(*context, data, plan);
        std::vector<oas::Pattern> patterns;
        for (const auto& p : points) patterns.push_back(p.pattern);
        cache->prepare(patterns);
    }
    const double buildSeconds = cache ? cache->buildSeconds() : 0.0;
    if (pipelineSeconds) *pipelineSeconds = buildSeconds;
    std::fprintf(stderr, "scene costs %s on %s: %zu points x %u rounds, %zu pipelines built in %.1f s (excluded)\n",
                 record.name.c_str(), costDeviceLabel(o.device), points.size(), o.rounds, cache ? cache->size() : 0,
                 buildSeconds);
    oas::render::Accumulation cpuSums(record.width, record.height);

    using Clock = std::chrono::steady_clock;
    for (std::uint32_t round = 0; round < o.rounds; ++round) {
        const auto roundStart = Clock::now();
        for (auto& p : points) {
            const std::uint32_t seed = 0x5eed0000u + round;
            if (onCpu) {
                // As `oas-render --device cpu` renders: the twin's batch size, all workers.
                cpuSums = oas::render::Accumulation(record.width, record.height);
                const auto start = Clock::now();
                oas::render::forEachBatch(record.width, record.height, p.spp, oas::render::kCpuSamplesPerBatch, seed,
                                          [&](const oas::render::SampleBatch& b) {
                                              oas::render::traceCpu(data, plan, p.pattern, b, cpuSums, o.cpuThreads);
                                          });
                p.times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
                continue;
            }
            auto& tracer = cache->get(p.pattern);
            tracer.clear();
            const auto start = Clock::now();
            oas::render::forEachBatch(record.width, record.height, p.spp, tracer.samplesPerBatch(), seed,
                                      [&](const oas::render::SampleBatch& b) { tracer.trace(b); });
            p.times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
        }
        std::fprintf(stderr, "scene costs %s: round %u/%u in %.1f s\n", record.name.c_str(), round + 1, o.rounds,
                     std::chrono::duration<double>(Clock::now() - roundStart).count());
    }
    std::vector<SceneCost> out;
    for (const auto& p : points) {
        SceneCost c = summarizeTimes(p.times);
        c.scene = record.name;
        c.sampler = p.sampler;
        c.spp = p.spp;
        c.runId = o.runId;
        c.machine = o.machine;
        c.device = onCpu ? std::string(kCpuTwinDeviceName) : context->deviceName();
        c.date = o.date;
        c.commit = o.commit;
        c.sources = renderSourcesHash();
        out.push_back(c);
    }
    return out;
}

}  // namespace oas::study
