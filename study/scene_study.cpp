#include "scene_study.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "image/image.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"
#include "stats.hpp"

namespace oas::study {
namespace {

using Clock = std::chrono::steady_clock;

/// The count of a ladder nearest (in log) to `target`.
double nearest(const std::vector<double>& counts, double target)
{
    double best = 0, bestD = 1e300;
    for (double c : counts) {
        const double d = std::abs(std::log(c / target));
        if (d < bestD) bestD = d, best = c;
    }
    return best;
}

bool isOa(const SamplerSpec& s) { return s.strength > 0; }

std::string sci(double v) { return std::isfinite(v) ? fmtG(v, 3) : "—"; }

/// One GPU tracer per pipeline specialization, reused across sample counts (the pattern is a push
/// constant). Lavapipe took ~17 s to build one path-tracing pipeline on this machine (1.5 s since
/// the tracer calls the sampler at one site), so all of a scene's pipelines are built up front on
/// every core (pipeline creation is thread-safe in Vulkan) and warmed up with one untimed dispatch:
/// builds and first-use costs stay out of the timings.
class TracerCache {
public:
    TracerCache(oas::vk::Context& context, const oas::render::SceneData& data, const oas::render::DimensionPlan& plan)
        : context_(context), data_(data), plan_(plan)
    {
    }
    void prepare(const std::vector<oas::Pattern>& patterns)
    {
        std::vector<oas::Pattern> todo;
        for (const auto& p : patterns)
            if (!find(p) && std::none_of(todo.begin(), todo.end(), [&](const oas::Pattern& q) {
                    return oas::specializationKey(q) == oas::specializationKey(p);
                }))
                todo.push_back(p);
        std::vector<std::unique_ptr<oas::render::GpuTracer>> made(todo.size());
        std::atomic<size_t> next{0};
        std::vector<std::thread> pool;
        std::exception_ptr failure;
        std::mutex failureMutex;
        for (unsigned t = 0; t < std::max(1u, std::thread::hardware_concurrency()); ++t)
            pool.emplace_back([&] {
                for (size_t i; (i = next++) < todo.size();) {
                    try {
                        made[i] = std::make_unique<oas::render::GpuTracer>(context_, data_, plan_, todo[i]);
                    } catch (...) {
                        std::lock_guard<std::mutex> lock(failureMutex);
                        failure = std::current_exception();
                    }
                }
            });
        for (auto& th : pool) th.join();
        if (failure) std::rethrow_exception(failure);
        for (auto& t : made) {
            oas::render::SampleBatch warm;
            warm.width = std::min<std::uint32_t>(8, std::uint32_t(data_.globals.image.x));
            warm.height = std::min<std::uint32_t>(8, std::uint32_t(data_.globals.image.y));
            t->trace(warm);
            tracers_.push_back(std::move(t));
        }
    }
    oas::render::GpuTracer& get(const oas::Pattern& pattern)
    {
        if (!find(pattern)) prepare({pattern});
        auto* t = find(pattern);
        t->setPattern(pattern);
        return *t;
    }

private:
    oas::render::GpuTracer* find(const oas::Pattern& pattern)
    {
        for (auto& t : tracers_)
            if (t->accepts(pattern)) return t.get();
        return nullptr;
    }
    oas::vk::Context& context_;
    const oas::render::SceneData& data_;
    const oas::render::DimensionPlan& plan_;
    std::vector<std::unique_ptr<oas::render::GpuTracer>> tracers_;
};

struct Render {
    oas::image::Image image;
    double seconds = 0;
};

Render render(oas::render::GpuTracer& tracer, const oas::render::DimensionPlan& plan, std::uint32_t width,
              std::uint32_t height, std::uint32_t spp, std::uint32_t seed)
{
    tracer.clear();
    const auto start = Clock::now();
    oas::render::forEachBatch(width, height, spp, oas::render::samplesPerBatch(plan), seed,
                              [&](const oas::render::SampleBatch& b) { tracer.trace(b); });
    Render r;
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    r.image = oas::image::imageFromAccumulation(tracer.accumulation(), width, height);
    return r;
}

std::string slug(std::string s)
{
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

}  // namespace

std::vector<SceneCase> studyScenes()
{
    return {
        {"cornell7d.json", 0.5, 0.5, 0.5, 0.5, "the moving, defocused sphere and its shadow (lower right quarter)"},
        {"blue_spheres9d.json", 0.0, 0.3, 0.55, 0.45, "the defocused, moving spheres on the left"},
        {"interior_deep.json", 0.25, 0.35, 0.5, 0.4, "the table and rug lit indirectly (centre)"},
    };
}

oas::image::Crop cropPixels(const SceneCase& c, std::uint32_t width, std::uint32_t height)
{
    oas::image::Crop crop;
    crop.x = std::min(width - 1, std::uint32_t(std::floor(c.cropX * width)));
    crop.y = std::min(height - 1, std::uint32_t(std::floor(c.cropY * height)));
    crop.w = std::clamp(std::uint32_t(std::lround(c.cropW * width)), 1u, width - crop.x);
    crop.h = std::clamp(std::uint32_t(std::lround(c.cropH * height)), 1u, height - crop.y);
    return crop;
}

std::vector<SceneCurve> curvesOf(const std::vector<SceneMeasurement>& measurements)
{
    std::vector<SceneCurve> curves;
    std::map<std::pair<std::string, std::string>, std::map<std::uint32_t, std::vector<const SceneMeasurement*>>> by;
    std::vector<std::pair<std::string, std::string>> order;
    for (const auto& m : measurements) {
        const auto key = std::make_pair(m.scene, m.sampler);
        if (!by.count(key)) order.push_back(key);
        by[key][m.spp].push_back(&m);
    }
    for (const auto& key : order) {
        SceneCurve c;
        c.scene = key.first;
        c.sampler = key.second;
        for (const auto& [spp, ms] : by[key]) {
            std::vector<double> t;
            double e = 0, ec = 0;
            for (auto* m : ms) {
                t.push_back(m->seconds);
                e += m->relMse;
                ec += m->relMseCrop;
            }
            c.spp.push_back(spp);
            c.seconds.push_back(median(t));
            c.relMse.push_back(e / ms.size());
            c.relMseCrop.push_back(ec / ms.size());
        }
        curves.push_back(std::move(c));
    }
    return curves;
}

std::string runSceneStudy(const SceneStudyOptions& o, const std::vector<SamplerSpec>& samplers, oas::vk::Context& context)
{
    const auto t0 = Clock::now();
    namespace fs = std::filesystem;
    const std::string imgDir = o.outDir + "/scenes";
    fs::create_directories(imgDir);
    const std::string deviceName = context.deviceName();

    std::vector<SceneCase> cases;
    for (const auto& c : studyScenes()) {
        const std::string stem = fs::path(c.file).stem().string();
        if (o.scenes.empty() || std::find(o.scenes.begin(), o.scenes.end(), stem) != o.scenes.end())
            cases.push_back(c);
    }
    if (cases.empty()) throw std::invalid_argument("--scene: none of the given names is a study scene "
                                                   "(cornell7d, blue_spheres9d, interior_deep)");

    std::vector<SceneMeasurement> all;
    CsvTable refCsv({"scene", "width", "height", "dims", "reference_sampler", "reference_spp", "ref_rel_mse",
                     "ref_rel_mse_crop", "seconds", "crop_x", "crop_y", "crop_w", "crop_h"});
    struct SceneInfo {
        std::string name;
        std::uint32_t width, height, dims;
        oas::image::Crop crop;
        double refErr, refErrCrop;
        std::string cropWhat;
        // trial-0 images per (sampler, spp), for the equal-time error pictures
        std::map<std::pair<std::string, std::uint32_t>, oas::image::Image> images;
        oas::image::Image reference;
    };
    std::vector<SceneInfo> infos;
    // Random and Halton also render at Bose's counts (matched spp with the OAs).
    const SamplerSpec bose = studySamplers().front();

    for (std::uint32_t si = 0; si < cases.size(); ++si) {
        const SceneCase& sc = cases[si];
        auto scene = oas::scene::loadScene(o.scenesDir + "/" + sc.file);
        scene.height = std::max(1u, scene.height * o.width / scene.width);
        scene.width = o.width;
        const auto plan = oas::render::planDimensions(scene);
        const auto data = oas::render::flattenScene(scene);
        TracerCache cache(context, data, plan);
        SceneInfo info;
        info.name = scene.name;
        info.width = scene.width;
        info.height = scene.height;
        info.dims = plan.usedDims;
        info.crop = cropPixels(sc, scene.width, scene.height);
        info.cropWhat = sc.cropWhat;

        // Every (sampler, spp) pattern first, so that all pipelines can be built up front.
        std::vector<std::vector<std::pair<std::uint32_t, oas::Pattern>>> runs(samplers.size());
        std::vector<oas::Pattern> allPatterns;
        for (std::uint32_t k = 0; k < samplers.size(); ++k) {
            const SamplerSpec& s = samplers[k];
            std::vector<std::uint32_t> ladder = countLadder(s, plan.sampleDims, o.minSpp, o.maxSpp);
            // Random and Halton take any count: add the Bose counts, for comparisons at matched spp.
            if (s.sampler == "random" || s.sampler == "halton") {
                for (auto c : countLadder(bose, plan.sampleDims, o.minSpp, o.maxSpp)) ladder.push_back(c);
                std::sort(ladder.begin(), ladder.end());
                ladder.erase(std::unique(ladder.begin(), ladder.end()), ladder.end());
            }
            for (std::uint32_t spp : ladder) {
                try {
                    runs[k].push_back({spp, oas::makePattern(patternRequest(s, spp, plan.sampleDims))});
                    allPatterns.push_back(runs[k].back().second);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "  skip %s at %u spp: %s\n", s.label.c_str(), spp, e.what());
                }
            }
        }
        SamplerSpec sobolSpec{"Sobol", "sobol", "cmj", 0, false, true};
        const oas::Pattern refPattern = oas::makePattern(patternRequest(sobolSpec, o.referenceSpp / 2, plan.sampleDims));
        allPatterns.push_back(refPattern);
        const auto tp = Clock::now();
        cache.prepare(allPatterns);
        std::fprintf(stderr, "  pipelines built in %.0f s\n", std::chrono::duration<double>(Clock::now() - tp).count());
        // Reference: Owen-scrambled Sobol, two independent halves. For independent renders A and
        // B of equal variance, E relMSE(A, B) = 2 var(half) and the average's variance is
        // var(half) / 2, so relMSE(A, B) / 4 estimates the reference's own relative error. It is
        // subtracted from every measurement (E relMSE(I, R) = relMSE(I) + relMSE(R) for independent
        // I, R) and reported, so the reader can see how far below the smallest measurement it is.
        std::fprintf(stderr, "[scenes] %s %ux%u, %uD: reference (Sobol, 2 x %u spp)...\n", info.name.c_str(),
                     scene.width, scene.height, plan.usedDims, o.referenceSpp / 2);
        auto& refTracer = cache.get(refPattern);
        const Render a = render(refTracer, plan, scene.width, scene.height, o.referenceSpp / 2, 0xA5A5A5A5u + si);
        const Render b = render(refTracer, plan, scene.width, scene.height, o.referenceSpp / 2, 0x5A5A5A5Au + si);
        info.reference = a.image;
        for (std::size_t i = 0; i < info.reference.rgba.size(); ++i)
            info.reference.rgba[i] = 0.5f * (a.image.rgba[i] + b.image.rgba[i]);
        info.refErr = oas::image::compare(a.image, b.image).relMse / 4;
        info.refErrCrop = oas::image::compare(a.image, b.image, info.crop).relMse / 4;
        refCsv.add({info.name, std::to_string(info.width), std::to_string(info.height), std::to_string(info.dims),
                    "sobol", std::to_string(o.referenceSpp), fmtG(info.refErr), fmtG(info.refErrCrop),
                    fmtG(a.seconds + b.seconds), std::to_string(info.crop.x), std::to_string(info.crop.y),
                    std::to_string(info.crop.w), std::to_string(info.crop.h)});
        oas::image::writePngPreview(imgDir + "/" + info.name + "_reference.png", info.reference);

        for (std::uint32_t k = 0; k < samplers.size(); ++k) {
            const SamplerSpec& s = samplers[k];
            for (const auto& [spp, pattern] : runs[k]) {
                auto& tracer = cache.get(pattern);
                for (std::uint32_t t = 0; t < o.trials; ++t) {
                    const Render r = render(tracer, plan, scene.width, scene.height, spp, mixSeed(si, k, spp, t));
                    SceneMeasurement m;
                    m.scene = info.name;
                    m.sampler = s.label;
                    m.pattern = oas::describe(pattern);
                    m.spp = spp;
                    m.trial = t;
                    m.seconds = r.seconds;
                    m.relMseRaw = oas::image::compare(r.image, info.reference).relMse;
                    m.relMseCropRaw = oas::image::compare(r.image, info.reference, info.crop).relMse;
                    m.relMse = m.relMseRaw - info.refErr;
                    m.relMseCrop = m.relMseCropRaw - info.refErrCrop;
                    all.push_back(m);
                    if (t == 0) info.images[{s.label, spp}] = r.image;
                }
            }
            std::fprintf(stderr, "  %s: %s done (%.0f s so far)\n", info.name.c_str(), s.label.c_str(),
                         std::chrono::duration<double>(Clock::now() - t0).count());
        }
        infos.push_back(std::move(info));
    }

    CsvTable csv({"scene", "sampler", "pattern", "spp", "trial", "seconds", "rel_mse", "rel_mse_crop", "rel_mse_raw",
                  "rel_mse_crop_raw"});
    for (const auto& m : all)
        csv.add({m.scene, m.sampler, m.pattern, std::to_string(m.spp), std::to_string(m.trial), fmtG(m.seconds),
                 fmtG(m.relMse), fmtG(m.relMseCrop), fmtG(m.relMseRaw), fmtG(m.relMseCropRaw)});
    csv.write(o.outDir + "/scenes.csv");
    refCsv.write(o.outDir + "/scene_references.csv");

    const auto curves = curvesOf(all);
    CsvTable curveCsv({"scene", "sampler", "spp", "seconds", "rel_mse", "rel_mse_crop"});
    for (const auto& c : curves)
        for (size_t i = 0; i < c.spp.size(); ++i)
            curveCsv.add({c.scene, c.sampler, fmtG(c.spp[i]), fmtG(c.seconds[i]), fmtG(c.relMse[i]),
                          fmtG(c.relMseCrop[i])});
    curveCsv.write(o.outDir + "/scene_curves.csv");

    auto curveOf = [&](const std::string& scene, const std::string& sampler) -> const SceneCurve* {
        for (const auto& c : curves)
            if (c.scene == scene && c.sampler == sampler) return &c;
        return nullptr;
    };
    auto valueAt = [&](const SceneCurve& c, double spp, bool crop) {
        for (size_t i = 0; i < c.spp.size(); ++i)
            if (c.spp[i] == spp) return crop ? c.relMseCrop[i] : c.relMse[i];
        return std::numeric_limits<double>::quiet_NaN();
    };
    // Random at a count it did not render (e.g. Addelman-Kempthorne's 162): its curve is dense
    // (powers of two and Bose's counts) and ∝ 1/spp, so log-log interpolation is accurate.
    auto cmj2dAt128 = [&](const std::string& scene) {
        const SceneCurve* cmj = curveOf(scene, "CMJ2D-pad");
        return cmj ? valueAt(*cmj, 128, false) : std::numeric_limits<double>::quiet_NaN();
    };
    auto randomAt = [&](const SceneCurve* rnd, double spp) {
        if (!rnd) return std::numeric_limits<double>::quiet_NaN();
        const double exact = valueAt(*rnd, spp, false);
        return std::isfinite(exact) ? exact : interpLogLog(rnd->spp, rnd->relMse, spp);
    };

    std::ostringstream md;
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    md << "## Scenes: relative MSE versus samples and versus time\n\n"
       << "- Device: " << deviceName << " (the CI machine's Vulkan; every figure below is lavapipe wall-clock time)\n"
       << "- Command: `build/" << o.command << "`" << (o.quick ? " (quick mode)" : " (full mode)") << "; scene part run time "
       << fmtF(seconds, 0) << " s\n"
       << "- Images " << o.width << " px wide; " << o.trials << " independent render(s) per (sampler, spp), "
       << "spp from " << o.minSpp << " to " << o.maxSpp
       << "; reference: Owen-scrambled Sobol at " << o.referenceSpp << " spp as two independent halves.\n"
       << "- relMSE = mean over pixels and R, G, B of (I − R)² / (R² + 0.01) (Rousselle et al.; the paper's metric), "
          "for the full image and for a crop; the reference's own relMSE, estimated from its two halves, is "
          "subtracted (table below).\n"
       << "- Time: wall-clock of the render's dispatches, median over the trials, pipeline build excluded. "
          "The machine is shared, so times carry a few per cent of noise.\n"
       << "- Data: [`scenes.csv`](study/scenes.csv) (every render), [`scene_curves.csv`](study/scene_curves.csv), "
          "[`scene_references.csv`](study/scene_references.csv); figures `study/scene_error_vs_spp.png`, "
          "`study/scene_error_vs_time.png`, `study/scene_equal_time.png`.\n\n";

    md << "| scene | size | integrand dims | crop | reference relMSE (full / crop) | smallest measured relMSE (full / crop) |\n"
          "|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        double minFull = 1e300, minCrop = 1e300;
        for (const auto& m : all)
            if (m.scene == info.name) minFull = std::min(minFull, m.relMse), minCrop = std::min(minCrop, m.relMseCrop);
        md << "| " << info.name << " | " << info.width << "×" << info.height << " | " << info.dims << " | "
           << info.crop.w << "×" << info.crop.h << " at (" << info.crop.x << ", " << info.crop.y << "): " << info.cropWhat
           << " | " << sci(info.refErr) << " / " << sci(info.refErrCrop) << " | " << sci(minFull) << " / " << sci(minCrop)
           << " |\n";
    }
    md << "\n![relMSE vs spp](study/scene_error_vs_spp.png)\n\n![relMSE vs time](study/scene_error_vs_time.png)\n\n";

    // --- At the paper's sample count (~121/128 spp) -------------------------------------------
    bool goal7d = false;
    std::string goal7dText;
    md << "### At the paper's sample count (about 121/128 spp)\n\n"
       << "Each sampler at its ladder count nearest 128 (OAs: 121 = 11², Bose–Bush 128, Addelman–Kempthorne 2q², "
          "CMJND s⁴; baselines 128; Random and Halton also at 121, a matched count). Ratios are to Random at the "
          "same count and to CMJ2D-pad at 128, the paper's comparison.\n\n"
       << "| scene | sampler | spp | relMSE | crop relMSE | ÷ Random (same spp) | ÷ CMJ2D-pad@128 | ms per frame |\n"
          "|---|---|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = curveOf(info.name, "Random");
        const double cmj128 = cmj2dAt128(info.name);
        double bestOa = 1e300;
        std::string bestOaName;
        double bestOaRnd = NAN;
        for (const auto& s : samplers) {
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!c) continue;
            const double n = nearest(c->spp, 128);
            const double e = valueAt(*c, n, false), ec = valueAt(*c, n, true);
            const double r = randomAt(rnd, n);
            double secs = NAN;
            for (size_t i = 0; i < c->spp.size(); ++i)
                if (c->spp[i] == n) secs = c->seconds[i];
            md << "| " << info.name << " | " << s.label << " | " << n << " | " << sci(e) << " | " << sci(ec) << " | "
               << (std::isfinite(r) ? fmtF(e / r, 2) : "—") << " | " << (std::isfinite(cmj128) ? fmtF(e / cmj128, 2) : "—")
               << " | " << fmtF(secs * 1000, 0) << " |\n";
            if (isOa(s) && e < bestOa) bestOa = e, bestOaName = s.label + "@" + fmtG(n), bestOaRnd = r;
        }
        if (info.name == "cornell7d" && std::isfinite(bestOaRnd) && std::isfinite(cmj128)) {
            goal7d = bestOa <= 0.5 * bestOaRnd && bestOa < cmj128;
            goal7dText = "best OA " + bestOaName + ": relMSE " + sci(bestOa) + " = " + fmtF(bestOa / bestOaRnd, 2) +
                         "× Random at the same spp (goal ≤ 0.50) and " + fmtF(bestOa / cmj128, 2) +
                         "× CMJ2D-pad@128 (goal < 1)";
        }
    }
    // Side by side with the paper (DESIGN §4: relative MSE, PBRT-v3, per-pixel samplers). Ratios,
    // not absolute errors: the scenes are ours, modelled on the paper's.
    struct PaperValue {
        const char* scene;
        const char* sampler;
        double relMse;
    };
    static const PaperValue paper[] = {
        {"cornell7d", "Random", 1.481e-3},      {"cornell7d", "Jittered2D-pad", 1.036e-3},
        {"cornell7d", "CMJ2D-pad", 8.721e-4},   {"cornell7d", "ZeroTwo-pad", 8.299e-4},
        {"cornell7d", "Halton", 7.819e-4},      {"cornell7d", "Sobol", 6.510e-4},
        {"cornell7d", "BushMJ(t=2)", 7.864e-4}, {"cornell7d", "BoseCMJ", 7.680e-4},
        {"blue_spheres9d", "Random", 3.959e-3}, {"blue_spheres9d", "CMJ2D-pad", 1.557e-3},
        {"blue_spheres9d", "Sobol", 1.117e-3},  {"blue_spheres9d", "BoseCMJ", 1.215e-3},
        {"interior_deep", "Random", 8.701e-4},  {"interior_deep", "CMJ2D-pad", 6.524e-4},
        {"interior_deep", "Sobol", 5.994e-4},   {"interior_deep", "BoseCMJ", 6.024e-4},
    };
    auto paperOf = [&](const std::string& scene, const std::string& sampler) {
        for (const auto& p : paper)
            if (scene == p.scene && sampler == p.sampler) return p.relMse;
        return std::numeric_limits<double>::quiet_NaN();
    };
    md << "\n#### Side by side with the paper\n\n"
       << "The paper's relative MSE (DESIGN §4; CornellBox 7D and BlueSpheres 9D at 121/128 spp, Barcelona 43D "
          "at 3969/4096 spp, where its \"OA\" row is shown against our BoseCMJ) as ratios to its Random and its "
          "CMJ2D-pad, next to ours at about 128 spp (our Random at the same count as the sampler; our "
          "interior_deep stands in for Barcelona at 32× fewer samples).\n\n"
       << "| scene | sampler | paper ÷ Random | ours ÷ Random | paper ÷ CMJ2D-pad | ours ÷ CMJ2D-pad@128 |\n"
          "|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = curveOf(info.name, "Random");
        const double cmj128 = cmj2dAt128(info.name);
        for (const auto& s : samplers) {
            const double pv = paperOf(info.name, s.label);
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!std::isfinite(pv) || !c) continue;
            const double n = nearest(c->spp, 128), e = valueAt(*c, n, false);
            const double r = randomAt(rnd, n);
            auto ratio = [](double a, double b) { return std::isfinite(a / b) ? fmtF(a / b, 2) : std::string("—"); };
            md << "| " << info.name << " | " << s.label << " | " << ratio(pv, paperOf(info.name, "Random")) << " | "
               << ratio(e, r) << " | " << ratio(pv, paperOf(info.name, "CMJ2D-pad")) << " | " << ratio(e, cmj128)
               << " |\n";
        }
    }
    md << "\n**Goal (7D scene at about 121 spp: best OA ≤ 0.50 × Random and below CMJ2D-pad): "
       << (goal7dText.empty() ? "not measured" : goal7d ? "met" : "not met") << "**";
    md << (goal7dText.empty() ? " (cornell7d not studied)" : " — " + goal7dText) << ".\n\n";

    // --- Equal time and time to target ---------------------------------------------------------
    // Budgets are fixed before looking at any result: the time Owen-scrambled Sobol takes at 128 spp,
    // and the largest time every sampler's curve reaches (the smallest of their longest renders).
    int scenesOaWins[2] = {0, 0};
    md << "### Error at equal time\n\n"
       << "relMSE read off each sampler's measured error-versus-time curve (log-log interpolation between "
          "measured points; — where the budget lies outside the sampler's measured range) at two budgets per "
          "scene: T₁, the time Sobol took at 128 spp, and T₂, the largest budget every sampler's curve reaches (the "
          "shortest of the samplers' longest renders). Ratios are to Sobol.\n\n"
       << "| scene | sampler | relMSE @ T₁ | ÷ Sobol | relMSE @ T₂ | ÷ Sobol |\n|---|---|---|---|---|---|\n";
    std::map<std::string, double> budgetOf;  // scene -> T1 (for the images)
    std::ostringstream answer;                // the short answer at the top of the section
    for (const auto& info : infos) {
        const SceneCurve* sob = curveOf(info.name, "Sobol");
        if (!sob) continue;
        double budgets[2] = {NAN, 1e300};
        for (size_t i = 0; i < sob->spp.size(); ++i)
            if (sob->spp[i] == 128) budgets[0] = sob->seconds[i];
        for (const auto& c : curves)  // the largest budget every sampler's curve reaches
            if (c.scene == info.name && !c.seconds.empty())
                budgets[1] = std::min(budgets[1], *std::max_element(c.seconds.begin(), c.seconds.end()));
        budgetOf[info.name] = budgets[0];
        md << "| " << info.name << " | *budgets* | T₁ = " << fmtF(budgets[0] * 1000, 0) << " ms | | T₂ = "
           << fmtF(budgets[1] * 1000, 0) << " ms | |\n";
        double sobAt[2], bestOa[2] = {1e300, 1e300};
        std::vector<std::pair<double, std::string>> ranking[2];
        std::string bestName[2];
        for (int b = 0; b < 2; ++b) sobAt[b] = interpLogLog(sob->seconds, sob->relMse, budgets[b]);
        for (const auto& s : samplers) {
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!c) continue;
            // Curves may be non-monotone in time for tiny renders (noise): sort by time.
            std::vector<std::pair<double, double>> pts;
            for (size_t i = 0; i < c->spp.size(); ++i) pts.push_back({c->seconds[i], c->relMse[i]});
            std::sort(pts.begin(), pts.end());
            std::vector<double> ts, es;
            for (auto& [t, e] : pts) ts.push_back(t), es.push_back(e);
            md << "| " << info.name << " | " << s.label;
            for (int b = 0; b < 2; ++b) {
                const double e = interpLogLog(ts, es, budgets[b]);
                md << " | " << sci(e) << " | " << (std::isfinite(e) ? fmtF(e / sobAt[b], 2) : "—");
                if (std::isfinite(e)) ranking[b].push_back({e, s.label});
                if (isOa(s) && std::isfinite(e) && e < bestOa[b]) bestOa[b] = e, bestName[b] = s.label;
            }
            md << " |\n";
        }
        for (int b = 0; b < 2; ++b)
            if (bestOa[b] <= sobAt[b]) ++scenesOaWins[b];
        answer << "| " << info.name << " (" << info.dims << "D)";
        for (int b = 0; b < 2; ++b) {
            std::sort(ranking[b].begin(), ranking[b].end());
            answer << " |";
            for (size_t i = 0; i < std::min<size_t>(3, ranking[b].size()); ++i)
                answer << (i ? ", " : " ") << ranking[b][i].second << " " << fmtF(ranking[b][i].first / sobAt[b], 2);
        }
        answer << " |\n";
    }
    const bool goalTime = scenesOaWins[0] >= 2 && scenesOaWins[1] >= 2;
    std::ostringstream head;
    head << "### The short answer: lowest error for the same render time\n\n"
         << "The three samplers with the lowest relMSE at equal render time on lavapipe, with their error ÷ "
            "Owen-scrambled Sobol's (below 1: better than Sobol). T₁ is Sobol's time at 128 spp, T₂ the longest "
            "budget every sampler reached; the tables below give every sampler, the counts, the crops and the "
            "costs.\n\n| scene | best at T₁ (÷ Sobol) | best at T₂ (÷ Sobol) |\n|---|---|---|\n"
         << answer.str() << "\n";
    md << "\n**Goal (at equal time, the best OA at or below Owen-scrambled Sobol on at least two of three scenes): "
       << (goalTime ? "met" : "not met") << "** — scenes where the best OA is at or below Sobol: " << scenesOaWins[0]
       << " of " << infos.size() << " at T₁, " << scenesOaWins[1] << " of " << infos.size() << " at T₂.\n\n";

    md << "### Time to reach a target error\n\n"
       << "Targets per scene: the relMSE Random reaches at 128 spp and at " << o.maxSpp
       << " spp. Time read off each curve (first crossing, log-log interpolation); ≤ marks a sampler already "
          "below the target at its smallest count, > one that does not reach it within the measured range.\n\n"
       << "| scene | sampler | time to target 1 (ms) | ÷ Random | time to target 2 (ms) | ÷ Random |\n|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = curveOf(info.name, "Random");
        if (!rnd) continue;
        const double targets[2] = {valueAt(*rnd, 128, false), valueAt(*rnd, o.maxSpp, false)};
        double rndTime[2];
        for (int b = 0; b < 2; ++b) rndTime[b] = firstCrossing(rnd->seconds, rnd->relMse, targets[b]).x;
        md << "| " << info.name << " | *targets* | relMSE " << sci(targets[0]) << " | | relMSE " << sci(targets[1])
           << " | |\n";
        for (const auto& s : samplers) {
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!c) continue;
            md << "| " << info.name << " | " << s.label;
            for (int b = 0; b < 2; ++b) {
                const Crossing x = firstCrossing(c->seconds, c->relMse, targets[b]);
                if (!x.found)
                    md << " | > " << fmtF(c->seconds.back() * 1000, 0) << " | —";
                else
                    md << " | " << (x.atFirst ? "≤ " : "") << fmtF(x.x * 1000, 0) << " | "
                       << fmtF(x.x / rndTime[b], 2);
            }
            md << " |\n";
        }
    }

    // --- Sampler cost inside a frame -----------------------------------------------------------
    md << "\n### Sampler cost inside a frame\n\n"
       << "Time per sample per pixel from a least-squares line of render time on spp over each sampler's "
          "ladder; the share is the part of the frame time above independent (Random) sampling, "
          "1 − t_Random / t_sampler, i.e. what generating that sampler's numbers costs inside the path "
          "tracer.\n\n| sampler |";
    for (const auto& info : infos) md << " " << info.name << " Mpaths/s | share |";
    md << "\n|---|";
    for (size_t i = 0; i < infos.size(); ++i) md << "---|---|";
    md << "\n";
    std::map<std::string, double> perSampleRandom;
    for (const auto& info : infos)
        if (const SceneCurve* r = curveOf(info.name, "Random")) perSampleRandom[info.name] = fitLine(r->spp, r->seconds).slope;
    for (const auto& s : samplers) {
        md << "| " << s.label;
        for (const auto& info : infos) {
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!c || c->spp.size() < 2) {
                md << " | — | —";
                continue;
            }
            const double perSample = fitLine(c->spp, c->seconds).slope;
            const double mpaths = double(info.width) * info.height / perSample / 1e6;
            md << " | " << fmtF(mpaths, 2) << " | " << fmtF(100 * (1 - perSampleRandom[info.name] / perSample), 0) << "%";
        }
        md << " |\n";
    }

    // --- Equal-time error images ---------------------------------------------------------------
    // For each sampler, the trial-0 render whose time is nearest (in log) to the budget T1.
    CsvTable eq({"scene", "sampler", "spp", "seconds", "budget_seconds", "rel_mse", "image"});
    for (const auto& info : infos) {
        const double budget = budgetOf.count(info.name) ? budgetOf[info.name] : NAN;
        if (!std::isfinite(budget)) continue;
        for (const auto& s : samplers) {
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!c) continue;
            size_t best = 0;
            for (size_t i = 1; i < c->spp.size(); ++i)
                if (std::abs(std::log(c->seconds[i] / budget)) < std::abs(std::log(c->seconds[best] / budget))) best = i;
            const std::uint32_t spp = std::uint32_t(c->spp[best]);
            const auto it = info.images.find({s.label, spp});
            if (it == info.images.end()) continue;
            const std::string file = info.name + "_" + slug(s.label) + "_error.png";
            oas::image::writePngPreview(imgDir + "/" + file, oas::image::falseColourError(it->second, info.reference));
            const std::string beauty = info.name + "_" + slug(s.label) + ".png";
            oas::image::writePngPreview(imgDir + "/" + beauty, it->second);
            eq.add({info.name, s.label, std::to_string(spp), fmtG(c->seconds[best]), fmtG(budget),
                    fmtG(oas::image::compare(it->second, info.reference).relMse - info.refErr), file});
        }
    }
    eq.write(o.outDir + "/scene_equal_time.csv");
    md << "\n### Error images at equal time\n\n"
       << "Per-pixel relative squared error in false colour (log scale, 1e-5 to 10, dark to bright; the ramp of "
          "`oas-diff`), for each sampler's render whose time is nearest the budget T₁ (its spp and time are in "
          "[`scene_equal_time.csv`](study/scene_equal_time.csv) and in the panel titles).\n\n"
       << "![equal-time error images](study/scene_equal_time.png)\n\n";
    // The short answer goes right below the section's list of settings.
    std::string text = md.str();
    const size_t at = text.find("\n| scene | size |");
    return text.substr(0, at + 1) + head.str() + text.substr(at + 1);
}

}  // namespace oas::study
