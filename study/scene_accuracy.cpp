// The scene part's accuracy run (runSceneStudy): per scene its reference (or the kept one of a
// sampler shard or top-up), every sampler's renders at every count of its ladder from a shared
// render-time budget, the rare pixels' own renders on the CPU and the equal-time error images;
// then the merge with the scenes measured before, and the section from the files written.
#include "scene_study.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <thread>

#include "image/image.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"
#include "scene_costs.hpp"
#include "scene_internal.hpp"
#include "stats.hpp"
#include "tracer_cache.hpp"

namespace oas::study {

using detail::costsIn;
using detail::readEqualTimeRows;
using detail::writeSceneData;

namespace {

using Clock = std::chrono::steady_clock;

struct Render {
    oas::image::Image image;
    double seconds = 0;
};

Render render(oas::render::GpuTracer& tracer, std::uint32_t width, std::uint32_t height, std::uint32_t spp, std::uint32_t seed)
{
    tracer.clear();
    const auto start = Clock::now();
    oas::render::forEachBatch(width, height, spp, tracer.samplesPerBatch(), seed,
                              [&](const oas::render::SampleBatch& b) { tracer.trace(b); });
    Render r;
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    r.image = tracer.accumulation().image();
    return r;
}

std::string slug(std::string s)
{
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

}  // namespace

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
        if (o.scenes.empty() || std::find(o.scenes.begin(), o.scenes.end(), stem) != o.scenes.end()) cases.push_back(c);
    }
    if (cases.empty())
        throw std::invalid_argument("--scene: none of the given names is a study scene "
                                    "(cornell7d, blue_spheres9d, interior_deep)");

    // The scenes measured before (other shards): kept, and merged with this run's at the end.
    const std::string refPath = o.outDir + "/scene_references.csv", csvPath = o.outDir + "/scenes.csv",
                      eqPath = o.outDir + "/scene_equal_time.csv";
    std::vector<SceneRecord> keptRecords;
    std::vector<SceneMeasurement> keptMeasurements;
    std::vector<std::vector<std::string>> keptEq;
    if (fs::exists(refPath) && fs::exists(csvPath)) {
        try {
            keptRecords = readSceneRecords(refPath);
            keptMeasurements = readSceneMeasurements(csvPath);
            keptEq = readEqualTimeRows(eqPath);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "note: the earlier scene data are not merged (%s); the section has only the scenes run now\n",
                         e.what());
            keptRecords.clear();
            keptMeasurements.clear();
            keptEq.clear();
        }
    }
    // A sample's seed uses the sampler's place in studySamplers(), not in this run's list, so that
    // the samplers of different shards never share seeds.
    const auto every = studySamplers();
    auto seedIndex = [&](std::uint32_t k) {
        for (std::uint32_t i = 0; i < every.size(); ++i)
            if (every[i].label == samplers[k].label) return i;
        return std::uint32_t(every.size() + k);
    };

    std::vector<SceneMeasurement> all;
    std::vector<SceneRecord> records;
    std::vector<std::string> joinedScenes;          // sampler shards and top-ups that joined the scene's earlier record
    std::vector<std::vector<std::string>> freshEq;  // scene_equal_time.csv rows of this run
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
        const auto sceneStart = Clock::now();
        SceneRecord info;
        // trial-0 images per (sampler, spp), for the equal-time error pictures
        std::map<std::pair<std::string, std::uint32_t>, oas::image::Image> images;
        oas::image::Image reference;
        info.device = deviceName;
        info.machine = o.machine;
        info.date = o.date;
        info.command = o.command;
        info.modeLabel = o.modeLabel;
        info.minSpp = o.minSpp;
        info.maxSpp = o.maxSpp;
        info.paperHighSpp = sc.paperHighCount && o.paperHighSpp > o.maxSpp ? o.paperHighSpp : 0;
        info.minTrials = o.minTrials;
        info.maxTrials = std::max(o.minTrials, o.maxTrials);
        info.relSeTarget = o.relSeTarget;
        info.extraSeconds = o.extraSecondsPerScene;
        info.rareCount = std::uint32_t(o.rarePixels >= 0 ? o.rarePixels : sc.rarePixels);
        info.name = scene.name;
        info.width = scene.width;
        info.height = scene.height;
        info.dims = plan.usedDims;
        info.crop = cropPixels(sc, scene.width, scene.height);

        // The sampler's counts in this scene.
        auto ladderOf = [&](const SamplerSpec& s) {
            std::vector<std::uint32_t> ladder = countLadder(s, plan.sampleDims, o.minSpp, o.maxSpp);
            // Random and Halton take any count: add the Bose counts, for comparisons at matched spp.
            const bool anyCount = s.sampler == "random" || s.sampler == "halton";
            if (anyCount)
                for (auto c : countLadder(bose, plan.sampleDims, o.minSpp, o.maxSpp)) ladder.push_back(c);
            // The paper's high count: the sampler's valid count nearest paperHighSpp. Halton takes
            // Bose's; Random every sampler's, so that each is compared with Random at its own count
            // (no extrapolation beyond the ladder).
            if (sc.paperHighCount && o.paperHighSpp > o.maxSpp) {
                std::vector<const SamplerSpec*> from{anyCount ? &bose : &s};
                if (s.sampler == "random")
                    for (const auto& other : every) from.push_back(&other);
                for (const SamplerSpec* f : from)
                    if (const std::uint32_t c = nearestCount(f->sampler == "random" || f->sampler == "halton" ? bose : *f,
                                                             plan.sampleDims, o.paperHighSpp))
                        ladder.push_back(c);
            }
            std::sort(ladder.begin(), ladder.end());
            ladder.erase(std::unique(ladder.begin(), ladder.end()), ladder.end());
            return ladder;
        };
        // Every (sampler, spp) pattern first, so that all pipelines can be built up front.
        std::vector<std::vector<std::pair<std::uint32_t, oas::Pattern>>> runs(samplers.size());
        std::vector<oas::Pattern> allPatterns;
        for (std::uint32_t k = 0; k < samplers.size(); ++k) {
            const SamplerSpec& s = samplers[k];
            for (std::uint32_t spp : ladderOf(s)) {
                try {
                    runs[k].push_back({spp, oas::makePattern(patternRequest(s, spp, plan.sampleDims))});
                    allPatterns.push_back(runs[k].back().second);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "  skip %s at %u spp: %s\n", s.label.c_str(), spp, e.what());
                }
            }
        }
        SamplerSpec sobolSpec{"Sobol", "sobol", "cmj", 0, false, true};
        // A sampler shard joins the scene's earlier record (and reuses its reference image) when
        // the settings match; otherwise the scene starts over.
        const std::string refExr = imgDir + "/" + info.name + "_reference.exr";
        const SceneRecord* kept = nullptr;
        for (const auto& r : keptRecords)
            if (r.name == info.name) kept = &r;
        const bool takeKept = o.shardTakesKeptSettings && kept;
        if (takeKept) {
            info.minTrials = kept->minTrials;
            info.maxTrials = kept->maxTrials;
        }
        // The reference has 16x the samples of the scene's largest count (a power of two, so that
        // each half is a Sobol count), unless the caller chose one or the shard joins a record.
        // The largest count is the mode's, over every sampler of it, not only this shard's.
        std::uint32_t largest = 0;
        for (const auto& r : runs)
            for (const auto& [spp, pattern] : r) largest = std::max(largest, spp);
        for (const SamplerSpec& s : o.modeSamplers)
            for (std::uint32_t spp : ladderOf(s)) {
                if (spp <= largest) continue;
                try {
                    oas::makePattern(patternRequest(s, spp, plan.sampleDims));  // a count the sampler can make
                    largest = spp;
                } catch (const std::exception&) {
                }
            }
        std::uint32_t referenceSpp = o.referenceSpp;
        if (referenceSpp == 0 && takeKept) referenceSpp = kept->referenceSpp;
        if (referenceSpp == 0) {
            referenceSpp = 256;
            while (referenceSpp < 16ull * largest && referenceSpp < (1u << 24)) referenceSpp *= 2;
        }
        info.referenceSpp = referenceSpp;
        info.largestSpp = largest;
        bool joined = false, rebuildReference = false;
        // A shard that cannot join starts the scene over, with a note; a top-up stops instead (it
        // was asked to add to the earlier renders, not to replace them).
        auto cannotJoin = [&](const std::string& why) {
            if (o.topUp)
                throw std::invalid_argument("--scene-top-up: " + info.name + " cannot be topped up: " + why +
                                            "; run it without --scene-top-up");
            if (o.mustJoin) throw std::invalid_argument("--scene-join: " + info.name + " cannot join its kept record: " + why);
            std::fprintf(stderr, "note: %s starts over: %s\n", info.name.c_str(), why.c_str());
        };
        if ((o.topUp || o.mustJoin) && !kept) cannotJoin("it has no earlier record in " + refPath);
        if ((o.samplerShard || o.topUp || o.mustJoin) && kept) {
            // A top-up may raise the renders-per-point cap (that is what it is for), not lower it.
            SceneRecord asKept = info;
            if (o.topUp && info.maxTrials >= kept->maxTrials) asKept.maxTrials = kept->maxTrials;
            std::string why;
            if (!sameSceneSettings(*kept, asKept, &why)) {
                cannotJoin("its earlier rows were measured with other settings (" + why + ")");
            } else if (!fs::exists(refExr) && !o.rebuildReferenceWith.empty()) {
                rebuildReference = true;  // rendered again below, and compared with the record
            } else if (!fs::exists(refExr)) {
                cannotJoin("its earlier reference image " + refExr +
                           " is missing (--scene-rebuild-reference renders it again)");
            } else {
                reference = oas::image::readExr(refExr);
                joined = reference.width == info.width && reference.height == info.height;
                if (!joined)
                    cannotJoin(refExr + " is " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                               ", not " + std::to_string(info.width) + "x" + std::to_string(info.height));
            }
        }
        if (rebuildReference) sobolSpec.sampler = o.rebuildReferenceWith;
        const oas::Pattern refPattern = oas::makePattern(patternRequest(sobolSpec, referenceSpp / 2, plan.sampleDims));
        if (!joined) allPatterns.push_back(refPattern);
        const auto tp = Clock::now();
        cache.prepare(allPatterns);
        std::fprintf(stderr, "  pipelines built in %.0f s\n", std::chrono::duration<double>(Clock::now() - tp).count());
        if (joined) {
            std::fprintf(stderr, "[scenes] %s %ux%u, %uD: %s, reference %s (Sobol, %u spp) reused\n", info.name.c_str(),
                         scene.width, scene.height, plan.usedDims, o.topUp ? "top-up of the kept renders" : "sampler shard",
                         refExr.c_str(), kept->referenceSpp);
            info.refErr = kept->refErr;
            info.refErrCrop = kept->refErrCrop;
            info.refErrSe = kept->refErrSe;
            info.refErrCropSe = kept->refErrCropSe;
            info.rarePixels = kept->rarePixels;
        } else {
            // Reference: Owen-scrambled Sobol, two independent halves. For independent renders A and
            // B of equal variance, E relMSE(A, B) = 2 var(half) and the average's variance is
            // var(half) / 2, so relMSE(A, B) / 4 estimates the reference's own relative error. It is
            // subtracted from every measurement (E relMSE(I, R) = relMSE(I) + relMSE(R) for independent
            // I, R) and reported, so the reader can see how far below the smallest measurement it is.
            std::fprintf(stderr, "[scenes] %s %ux%u, %uD: reference (Sobol, 2 x %u spp)...\n", info.name.c_str(), scene.width,
                         scene.height, plan.usedDims, referenceSpp / 2);
            auto& refTracer = cache.get(refPattern);
            const Render a = render(refTracer, scene.width, scene.height, referenceSpp / 2, 0xA5A5A5A5u + si);
            const Render b = render(refTracer, scene.width, scene.height, referenceSpp / 2, 0x5A5A5A5Au + si);
            reference = a.image;
            for (std::size_t i = 0; i < reference.rgba.size(); ++i)
                reference.rgba[i] = 0.5f * (a.image.rgba[i] + b.image.rgba[i]);
            info.refErr = oas::image::compare(a.image, b.image).relMse / 4;
            info.refErrCrop = oas::image::compare(a.image, b.image, info.crop).relMse / 4;
            const std::vector<double> halfErrors = pixelRelErrors(a.image, b.image);
            std::vector<double> cropErrors;
            for (std::uint32_t y = info.crop.y; y < info.crop.y + info.crop.h; ++y)
                for (std::uint32_t x = info.crop.x; x < info.crop.x + info.crop.w; ++x)
                    cropErrors.push_back(halfErrors[std::size_t(y) * info.width + x]);
            info.refErrSe = referenceErrorSe(halfErrors);
            info.refErrCropSe = referenceErrorSe(cropErrors);
            info.refSeconds = a.seconds + b.seconds;
            // The rare pixels: where the halves disagree most, relative to the value (independent
            // of every measured render, which all have other seeds).
            if (info.rareCount)
                info.rarePixels = formatPixels(rarePixelsOf(a.image, b.image, reference, info.rareCount), info.width);
            // A rebuilt reference joins the record only if it is the record's image: its own error
            // estimate, a function of every pixel of both halves, equal to 9 digits.
            if (rebuildReference) {
                const bool same = fmtG(info.refErr, 9) == fmtG(kept->refErr, 9) &&
                                  fmtG(info.refErrCrop, 9) == fmtG(kept->refErrCrop, 9);
                if (!same)
                    throw std::invalid_argument("--scene-rebuild-reference: " + info.name + "'s reference rendered with " +
                                                o.rebuildReferenceWith + " has error " + fmtG(info.refErr, 9) + " / " +
                                                fmtG(info.refErrCrop, 9) + ", the record's " + fmtG(kept->refErr, 9) +
                                                " / " + fmtG(kept->refErrCrop, 9) + ": not the same image");
                std::fprintf(stderr, "[scenes] %s: reference rebuilt with %s, the record's image (error %s)\n",
                             info.name.c_str(), o.rebuildReferenceWith.c_str(), fmtG(info.refErr, 9).c_str());
                info.refErrSe = kept->refErrSe;
                info.refErrCropSe = kept->refErrCropSe;
                info.refSeconds = kept->refSeconds;
                info.rarePixels = kept->rarePixels;
                joined = true;
            }
            oas::image::writePngPreview(imgDir + "/" + info.name + "_reference.png", reference);
            // Kept for later sampler shards of the scene (exact floats: the same relMSE for each).
            oas::image::writeExr(refExr, reference,
                                 {{"oas.scene", info.name}, {"oas.reference_spp", std::to_string(referenceSpp)}});
        }

        // Every (sampler, spp) of the scene is one point of a shared render-time budget
        // (SceneStudyOptions, budgetedMeans): minTrials renders each, then the extra renders go
        // where they shrink a relative s.e. most per second.
        struct Point {
            std::uint32_t sampler, spp;
            const oas::Pattern* pattern;
        };
        std::vector<Point> points;
        for (std::uint32_t k = 0; k < samplers.size(); ++k)
            for (const auto& [spp, pattern] : runs[k]) points.push_back({k, spp, &pattern});
        AdaptiveOptions ao;
        ao.nMin = info.minTrials;
        ao.nMax = info.maxTrials;
        ao.relTarget = o.relSeTarget;
        std::uint32_t lastSampler = ~0u;
        const size_t firstOfScene = all.size();
        const std::vector<std::uint32_t> rare = parsePixels(info.rarePixels, info.width, info.height);
        // A top-up's earlier rows per point: image renders by trial, rare-pixel batches by batch.
        std::vector<std::vector<SceneMeasurement>> keptImage(points.size()), keptRare(points.size());
        std::vector<std::uint32_t> keptCounts(points.size(), 0);
        if (o.topUp) {
            std::map<std::pair<std::string, std::uint32_t>, std::size_t> pointOf;  // (label, spp) -> point
            for (std::size_t p = 0; p < points.size(); ++p) pointOf[{samplers[points[p].sampler].label, points[p].spp}] = p;
            for (const auto& m : keptMeasurements) {
                const auto it = m.scene == info.name ? pointOf.find({m.sampler, m.spp}) : pointOf.end();
                if (it != pointOf.end()) (m.rareOnly ? keptRare : keptImage)[it->second].push_back(m);
            }
            for (std::size_t p = 0; p < points.size(); ++p) {
                for (auto* rows : {&keptImage[p], &keptRare[p]}) {
                    std::sort(rows->begin(), rows->end(), [](const auto& a, const auto& b) { return a.trial < b.trial; });
                    const std::uint32_t first = rows == &keptRare[p] ? 65536u : 0u;
                    for (std::uint32_t i = 0; i < rows->size(); ++i)
                        if ((*rows)[i].trial != first + i)
                            throw std::runtime_error(csvPath + ": " + info.name + " " + samplers[points[p].sampler].label + "@" +
                                                     std::to_string(points[p].spp) + ": trials are not " + std::to_string(first) +
                                                     ", " + std::to_string(first + 1) + ", ... (a top-up continues them)");
                }
                keptCounts[p] = std::uint32_t(keptImage[p].size());
            }
        }
        // What a render costs the shared budget (SceneStudyOptions::costRunCosts): its measured
        // seconds, or its point's seconds in the scene's cost run, so that the choice of the next
        // render does not depend on this run's timing.
        std::vector<double> costRunCost;
        if (o.costRunCosts && o.extraSecondsPerScene > 0) {
            const auto sceneCosts = costsOfScene(costsIn(o.outDir), info.name);
            if (sceneCosts.empty())
                throw std::invalid_argument("--scene-render-cost cost-run: " + info.name + " has no cost run in " + o.outDir +
                                            "/scene_costs.csv: run --parts scene-costs --scene " + info.name +
                                            " first, or give --scene-extra-seconds 0");
            for (const auto& pt : points) costRunCost.push_back(costRunSeconds(sceneCosts, samplers[pt.sampler].label, pt.spp));
        }
        // What budgetedMeans targets per render: the full image (without the rare pixels where
        // they get their own renders below) and the crop.
        auto drawOf = [&](std::size_t p, const SceneMeasurement& m) {
            return CostedDraw{{rare.empty() ? m.relMse : m.relMse - m.relMseRare, m.relMseCrop},
                              costRunCost.empty() ? m.seconds : costRunCost[p]};
        };
        const auto results = budgetedMeans(
            points.size(),
            [&](std::size_t p, std::uint32_t t) {
                const Point& pt = points[p];
                const SamplerSpec& s = samplers[pt.sampler];
                if (t == keptCounts[p] && pt.sampler != lastSampler) {
                    std::fprintf(stderr, "  %s: %s (%.0f s so far)\n", info.name.c_str(), s.label.c_str(),
                                 std::chrono::duration<double>(Clock::now() - t0).count());
                    lastSampler = pt.sampler;
                }
                if (t < keptCounts[p]) {
                    all.push_back(keptImage[p][t]);
                    return drawOf(p, keptImage[p][t]);
                }
                auto& tracer = cache.get(*pt.pattern);
                const Render r = render(tracer, scene.width, scene.height, pt.spp, mixSeed(si, seedIndex(pt.sampler), pt.spp, t));
                SceneMeasurement m;
                m.scene = info.name;
                m.sampler = s.label;
                m.pattern = oas::describe(*pt.pattern);
                m.spp = pt.spp;
                m.trial = t;
                m.seconds = r.seconds;
                m.relMseRaw = oas::image::compare(r.image, reference).relMse;
                m.relMseCropRaw = oas::image::compare(r.image, reference, info.crop).relMse;
                m.relMse = m.relMseRaw - info.refErr;
                m.relMseCrop = m.relMseCropRaw - info.refErrCrop;
                const std::vector<double> pixelErrors = pixelRelErrors(r.image, reference);
                for (auto pixel : rare) m.relMseRare += pixelErrors[pixel] / double(pixelErrors.size());
                m.relMseWorst = worstPixelsContribution(pixelErrors);
                all.push_back(m);
                if (t == 0) images[{s.label, pt.spp}] = r.image;
                // With the rare-pixel split the renders target the rest of the image; the rare
                // pixels' share gets its own renders below.
                return drawOf(p, m);
            },
            2, ao, o.extraSecondsPerScene, keptCounts);
        if (!rare.empty()) {
            std::fprintf(stderr, "  %s: rare pixels %s on the CPU (%.0f s so far)\n", info.name.c_str(), info.rarePixels.c_str(),
                         std::chrono::duration<double>(Clock::now() - t0).count());
            for (std::size_t p = 0; p < points.size(); ++p) {
                const Point& pt = points[p];
                const SamplerSpec& s = samplers[pt.sampler];
                // Batches of kRareBatch renders of the rare pixels while they can still bring the
                // stratified sum's s.e. (curvesOf) to the target (moreRareRendersHelp), at least 2
                // batches, at most maxRareRenders.
                const Estimate restE = results[p][0].estimate;
                std::vector<double> batches;
                for (const auto& m : keptRare[p]) {
                    all.push_back(m);
                    batches.push_back(m.relMseRare);
                }
                const std::uint32_t maxBatches = std::max(2u, o.maxRareRenders / kRareBatch);
                // The stratified sum so far (as curvesOf forms it): the rest of the image plus the
                // rare pixels' batches.
                auto sum = [&] { return sumOf(restE, estimateOf(batches)); };
                auto converged = [&](const Estimate& e) { return e.se <= o.relSeTarget * std::abs(e.mean); };
                while (batches.size() < maxBatches) {
                    if (batches.size() >= 2 && !moreRareRendersHelp(restE, estimateOf(batches), o.relSeTarget)) break;
                    const std::uint32_t batch = std::uint32_t(batches.size());
                    const auto start = Clock::now();
                    std::vector<double> shares(kRareBatch, 0.0);
                    std::atomic<std::uint32_t> next{0};
                    std::vector<std::thread> pool;
                    for (unsigned w = 0; w < std::max(1u, std::thread::hardware_concurrency()); ++w)
                        pool.emplace_back([&] {
                            oas::render::Accumulation scratch;
                            for (std::uint32_t j; (j = next++) < kRareBatch;) {
                                // Render seeds beyond any image render's trial (< 2^16), one per render.
                                const std::uint32_t seed =
                                    mixSeed(si, seedIndex(pt.sampler), pt.spp, 65536u + batch * kRareBatch + j);
                                shares[j] = rarePixelsShareCpu(data, plan, *pt.pattern, rare, pt.spp, seed, reference, scratch);
                            }
                        });
                    for (auto& th : pool) th.join();
                    SceneMeasurement m;
                    m.scene = info.name;
                    m.sampler = s.label;
                    m.pattern = oas::describe(*pt.pattern);
                    m.spp = pt.spp;
                    m.trial = 65536u + batch;
                    m.seconds = std::chrono::duration<double>(Clock::now() - start).count();
                    m.rareOnly = true;
                    for (double v : shares) m.relMseRare += v / kRareBatch;
                    all.push_back(m);
                    batches.push_back(m.relMseRare);
                }
                // One line per point: this stage runs for minutes in full mode, and a silent minute looks like a hang.
                const Estimate e = sum();
                const bool restAbove = restE.se > o.relSeTarget * std::abs(e.mean);
                std::fprintf(stderr, "    %s@%u: %zu rare renders, relMSE %.3g +- %.2g (%.0f%%%s, %.0f s so far)\n",
                             s.label.c_str(), pt.spp, batches.size() * kRareBatch, e.mean, e.se, 100.0 * e.relSe(),
                             converged(e) ? ""
                             : restAbove  ? ", cap: the image renders' part"
                                          : ", cap",
                             std::chrono::duration<double>(Clock::now() - t0).count());
            }
        }
        std::fprintf(stderr, "  %s done (%.0f s so far)\n", info.name.c_str(),
                     std::chrono::duration<double>(Clock::now() - t0).count());
        info.runSeconds = std::chrono::duration<double>(Clock::now() - sceneStart).count();

        // Equal-time error images: for each sampler, the trial-0 render whose time is nearest (in
        // log) to the budget T1, the time Sobol took at 128 spp (as in the section's equal-time table;
        // in a sampler shard without Sobol, from the scene's earlier shards).
        const std::vector<SceneMeasurement> mine(all.begin() + firstOfScene, all.end());
        const auto curves = curvesOf(mine, o.relSeTarget);
        std::vector<SceneMeasurement> sceneSoFar;
        for (const auto& m : joined ? mergeSamplerShard(keptMeasurements, mine) : mine)
            if (m.scene == info.name) sceneSoFar.push_back(m);
        double budget = NAN;
        for (const auto& c : curvesOf(sceneSoFar, o.relSeTarget))
            if (c.sampler == "Sobol")
                for (size_t i = 0; i < c.spp.size(); ++i)
                    if (c.spp[i] == 128) budget = c.seconds[i];
        for (const auto& c : curves) {
            if (!std::isfinite(budget) || c.spp.empty()) break;
            size_t best = 0;
            for (size_t i = 1; i < c.spp.size(); ++i)
                if (std::abs(std::log(c.seconds[i] / budget)) < std::abs(std::log(c.seconds[best] / budget))) best = i;
            const std::uint32_t spp = std::uint32_t(c.spp[best]);
            const auto it = images.find({c.sampler, spp});
            if (it == images.end()) continue;
            const std::string file = info.name + "_" + slug(c.sampler) + "_error.png";
            oas::image::writePngPreview(imgDir + "/" + file, oas::image::falseColourError(it->second, reference));
            oas::image::writePngPreview(imgDir + "/" + info.name + "_" + slug(c.sampler) + ".png", it->second);
            freshEq.push_back({info.name, c.sampler, std::to_string(spp), fmtG(c.seconds[best]), fmtG(budget),
                               fmtG(oas::image::compare(it->second, reference).relMse - info.refErr), file});
        }
        if (joined) {
            info = joinShardRecord(*kept, info);
            joinedScenes.push_back(info.name);
        }
        records.push_back(std::move(info));
    }

    // Merge with the scenes measured before (other shards), write the data, and build the section
    // from what was written: a section assembled later from the files alone is the same. A scene run
    // now replaces its earlier rows, except that a sampler shard which joined the scene's record
    // replaces only its own samplers' rows.
    const auto mergedRecords = mergeSceneRecords(keptRecords, records);
    auto isMerged = [&](const std::string& scene) {
        return std::any_of(mergedRecords.begin(), mergedRecords.end(), [&](const SceneRecord& r) { return r.name == scene; });
    };
    auto isFresh = [&](const std::string& scene) {
        return std::any_of(records.begin(), records.end(), [&](const SceneRecord& r) { return r.name == scene; });
    };
    auto isJoined = [&](const std::string& scene) {
        return std::find(joinedScenes.begin(), joinedScenes.end(), scene) != joinedScenes.end();
    };
    auto isFreshSampler = [&](const std::string& scene, const std::string& sampler) {
        return std::any_of(all.begin(), all.end(),
                           [&](const SceneMeasurement& m) { return m.scene == scene && m.sampler == sampler; });
    };
    std::vector<SceneMeasurement> keptNow;  // without the rows of the scenes that start over
    for (const auto& m : keptMeasurements)
        if (!isFresh(m.scene) || isJoined(m.scene)) keptNow.push_back(m);
    std::vector<SceneMeasurement> mergedMeasurements;
    for (auto& m : mergeSamplerShard(keptNow, all))
        if (isMerged(m.scene)) mergedMeasurements.push_back(std::move(m));  // no rows without a record
    std::vector<std::vector<std::string>> eqRows;
    // A top-up renders no new trial-0 images, so its scenes keep their equal-time pictures.
    for (const auto& row : keptEq)
        if (isMerged(row[0]) && (!isFresh(row[0]) || (isJoined(row[0]) && (o.topUp || !isFreshSampler(row[0], row[1])))))
            eqRows.push_back(row);
    eqRows.insert(eqRows.end(), freshEq.begin(), freshEq.end());
    return writeSceneData(o.outDir, mergedRecords, mergedMeasurements, std::move(eqRows), samplers);
}

}  // namespace oas::study
