// oas-study: convergence of the MSE of OA samplers and baselines on the paper's analytic
// integrands (Jarosz et al. 2019, Sec. on variance slopes). Writes docs/study/analytic.csv (every
// measurement), references.csv, slopes.csv, slopes.md, points.csv (2D projections) and
// docs/STUDY.md; study/plot.py draws the figures from the CSVs.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "analytic_part.hpp"
#include "apps/cli_main.hpp"
#include "cost_study.hpp"
#include "experiment.hpp"
#include "pair_study.hpp"
#include "progressive_part.hpp"
#include "scene_costs.hpp"
#include "scene_study.hpp"
#include "spectrum.hpp"
#include "integrands.hpp"
#include "oas_render_sources.h"  // generated: OAS_RENDER_SOURCES_PATHS
#include "section_io.hpp"
#include "stats.hpp"

using namespace oas::study;

namespace {

/// Full mode's render seconds per scene beyond the minimum renders (--scene-extra-seconds).
constexpr double kFullExtraSeconds = 1800;

/// UTC "YYYYMMDDTHHMMSSZ": run ids.
std::string timestamp()
{
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y%m%dT%H%M%SZ", std::gmtime(&now));
    return text;
}

/// The commit being timed, from git in the source tree: the short hash, with "-dirty" when the
/// render-time sources have uncommitted changes; "" where git or the repository is missing (an
/// exported tarball).
std::string sourceCommit()
{
    const std::string git = "git -C '" + std::string(OAS_SOURCE_DIR) + "' ";
    auto output = [](const std::string& command) {
        std::string text;
        if (std::FILE* pipe = ::popen((command + " 2>/dev/null").c_str(), "r")) {
            char buf[256];
            for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) text.append(buf, n);
            if (::pclose(pipe) != 0) return std::string();
        }
        while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
        return text;
    };
    const std::string commit = output(git + "rev-parse --short=12 HEAD");
    if (commit.empty()) return commit;
    const bool dirty = !output(git + "status --porcelain -- " + OAS_RENDER_SOURCES_PATHS).empty();
    return dirty ? commit + "-dirty" : commit;
}

/// `section` with "- Machine: <CPU> (<threads> threads), <date>" as its first list item (after the
/// heading line), so that every section names where and when it was measured.
std::string stamped(const std::string& section)
{
    const size_t eol = section.find('\n');
    if (eol == std::string::npos) return section;
    const size_t body = section.find_first_not_of('\n', eol);
    return section.substr(0, body) + "- Machine: " + cpuModel() + " (" + std::to_string(std::thread::hardware_concurrency()) +
           " threads), " + today() + "\n" + section.substr(body);
}

std::string readFile(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

std::string spectraSection(const std::string& command, bool quick, double seconds)
{
    std::ostringstream md;
    md << "## 2D projections and their power spectra\n\n"
       << "- Command: `build/" << command << "`" << (quick ? " (quick mode)" : "") << "; run time " << fmtF(seconds, 1) << " s\n"
       << "- Data: [`points.csv`](study/points.csv) (one randomization per sampler), [`spectra.csv`](study/spectra.csv) "
          "(periodogram |Σ exp(−2πi k·x)|²/N averaged over "
       << (quick ? 16 : 64) << " independent randomizations, integer k, DC set to 0; white noise is 1 everywhere)\n\n"
       << "Pairs within a block of a strength-2 OA show a dark cross (the Latin-hypercube axes) and a dark "
          "low-frequency disc (2D stratification: the picture Jarosz et al. 2019 use to explain the method); "
          "pairs across blocks keep only the cross, as a padded sampler does. CMJ offsets darken the lowest "
          "frequencies most but leave peaks at multiples of s along the axes; Halton's and CMJ2D's lattices "
          "show as peaks too. Sobol uses Joe and Kuo's direction numbers (new-joe-kuo-6.21201).\n\n"
       << "![2D projections](study/projections.png)\n\n![power spectra](study/spectra.png)\n\n";
    return md.str();
}

/// Lines of a section that state a goal's verdict ("**Goal ...").
std::string goalLines(const std::string& section)
{
    std::istringstream in(section);
    std::ostringstream out;
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("**Goal", 0) == 0 || line.rfind("**Met", 0) == 0 || line.rfind("**Not met", 0) == 0)
            out << "- " << line << "\n";
    return out.str();
}

/// The first-screen note for stale cost runs (SceneCosts.CommittedCostRunsAreCurrentOrTheFirstScreenSaysTheyAreStale).
std::string staleCostNote(const std::string& scenes)
{
    return "**Stale cost runs:** the equal-time figures below take their times from cost runs (" + scenes +
           ") timed on other render-time sources than today's (`docs/study/scene_costs.csv`, column `sources`; empty "
           "where a run predates the stamp), so they may have moved since. Rerun them with `scripts/study.sh --parts "
           "scene-costs`.\n";
}

/// docs/STUDY.md from the parts' sections in outDir (each states its own machine, date, command).
void assembleStudy(const std::string& studyMd, const std::string& outDir)
{
    std::string scenes = readFile(outDir + "/scenes.md");
    // The scene section's short answer (which sampler, at what time, on which machine) opens the
    // file, before any method text; the section keeps the rest.
    std::string answer;
    if (const size_t at = scenes.find("### The short answer"); at != std::string::npos) {
        const size_t end = scenes.find("\n| scene | device |", at);
        answer = scenes.substr(at, end == std::string::npos ? std::string::npos : end + 1 - at);
        scenes.erase(at, answer.size());
        answer.replace(0, std::string("### The short answer").size(), "## The short answer");
        // A cost run timed on other render-time sources than this build's says so first.
        const std::string costPath = outDir + "/scene_costs.csv";
        const auto stale = std::filesystem::exists(costPath) ? staleCostScenes(readSceneCosts(costPath)) : std::vector<std::string>{};
        if (!stale.empty()) {
            std::string names;
            for (const auto& scene : stale) names += (names.empty() ? "" : ", ") + scene;
            answer.insert(answer.find('\n') + 1, "\n" + staleCostNote(names));
        }
    }
    const std::string cost = readFile(outDir + "/cost.md"), analytic = readFile(outDir + "/analytic.md"),
                      spectra = readFile(outDir + "/spectra.md"), pairs = readFile(outDir + "/pairs.md"),
                      progressive = readFile(outDir + "/progressive.md");
    std::ostringstream o;
    o << "# Study: which sampler should I use, and at what cost?\n\n"
      << answer
      << "Orthogonal-array samplers (Jarosz et al. 2019) against the baselines of the paper, measured by this "
         "repository's own code. Regenerate everything with `scripts/study.sh` (full mode: every sampler, "
         "64 px, at least 6 renders per scene point plus up to "
      << kFullExtraSeconds
      << " s of further renders per "
         "scene where they shrink the error bars most, and the 7D and 9D scenes at the paper's 3969/4096 spp; many hours on "
         "2 cores, see below) or `scripts/study.sh --quick` (about 6 minutes); "
         "`build/oas-study --parts ...` reruns single "
         "parts, and this file is reassembled from the parts' sections in `docs/study/*.md`. Each section "
         "states the machine, date and command that made it. Assembled "
      << today() << " on " << cpuModel() << ".\n\n"
      << "Scope: in full mode the scene ladders run from 16 to 1024 spp (the 7D and 9D scenes also at the "
         "paper's 3969/4096) and images are 64 px wide, because lavapipe renders these scenes at a few Mpaths/s at most on 2 "
         "cores "
         "(the scene section's cost table gives each sampler's rate); its first table gives each scene's own "
         "settings. Errors and times are measured apart: errors from the accuracy renders (bit-identical on any "
         "machine, so they may be pooled over runs), times from one cost run per scene (scene_costs.csv). "
         "Every relMSE is a mean over independent renders "
         "with n and the standard error next to it (marked \"cap\" where the s.e. is still above 10% of the "
         "mean); verdicts are ties unless two numbers differ by more than twice their combined s.e. The scenes "
         "are ours (scenes/README.md), "
         "modelled on the paper's CornellBox 7D, BlueSpheres 9D and Barcelona 43D, so compare ratios with the "
         "paper's, not absolute errors.\n\n";
    if (scenes.find("- Mode: full mode for every scene") == std::string::npos && !scenes.empty())
        o << "> **Not every scene figure below is from the full mode**: the scene section's first table gives "
             "each scene's command and settings (smaller images, shorter ladders, fewer renders per point, or "
             "only some of the samplers). The "
             "full mode (every sampler, 64 px, ladders to 1024 spp and the 7D and 9D scenes at 4096, 6+ renders "
             "per point) takes 1 to 1.5 hours of lavapipe time per scene on 2 cores (that table's scene run "
             "time column has each scene's measured time); "
             "`scripts/study.sh --parts scenes --scene NAME` runs one scene and merges it into the section "
             "(shards), and `--scene NAME --only LABEL ...` some of its samplers (sampler shards, against the "
             "scene's kept reference). The other parts' sections say which mode made them.\n\n";
    o << "## Goals\n\n";
    if (!analytic.empty()) {
        std::istringstream in(analytic);
        std::string line;
        bool inGoal = false;
        while (std::getline(in, line)) {  // the analytic goal's verdict line
            if (line.rfind("### Goal", 0) == 0) inGoal = true;
            if (inGoal && line.rfind("**", 0) == 0) {
                o << "- Analytic, 2-additive binary step, strength-2 OA slopes ≤ −1.45: " << line << "\n";
                break;
            }
        }
    }
    if (const size_t at = progressive.find("- Goal (the progressive"); at != std::string::npos)
        o << "- Progressive: " << progressive.substr(at + 2, progressive.find('\n', at) - at - 2) << "\n";
    o << goalLines(scenes) << "\n";
    for (const std::string* part : {static_cast<const std::string*>(&scenes), &cost, &spectra, &analytic, &progressive, &pairs})
        if (!part->empty()) o << *part << "\n";
    writeSection(studyMd, o.str());
}

}  // namespace

/// The samplers the scene part renders: quick mode a subset, to keep it to minutes (one
/// path-tracing pipeline per construction x offset x field kind, ~1.5 s each on lavapipe, and the
/// renders themselves); the full mode every sampler.
static std::vector<SamplerSpec> sceneSamplersOf(const std::vector<SamplerSpec>& samplers, bool quick)
{
    std::vector<SamplerSpec> out;
    for (const auto& s : samplers)
        if (!quick || s.label == "BoseCMJ" || s.label == "Random" || s.label == "CMJ2D-pad" || s.label == "Sobol")
            out.push_back(s);
    return out;
}

int main(int argc, char** argv)
{
    CLI::App app{"oas-study: the sampler study (analytic MSE slopes, scene error vs spp and time, cost, projections and spectra) "
                 "-> docs/study, docs/STUDY.md"};
    bool quick = false, noPlot = false, sceneTopUp = false;
    std::uint32_t trials = 0, minSpp = 16, maxSpp = 0, rqmcLog2 = 16, rqmcReps = 64;
    unsigned threads = 0;
    std::vector<std::uint32_t> dimsList;
    std::vector<std::string> only;
    std::string outDir = "docs/study", studyMd = "docs/STUDY.md";
    app.add_flag("--quick", quick, "fewer trials and sizes (a few minutes on 2 cores)");
    app.add_option("--trials", trials,
                   "independent randomizations per (sampler, N) (the analytic part: quick 512, full 4096; the "
                   "progressive part: quick 256, full 16384)");
    app.add_option("--dims", dimsList, "dimensions to study (quick: 4 8; full: 4 8 16)");
    app.add_option("--min-spp", minSpp, "smallest sample count (16)");
    app.add_option("--max-spp", maxSpp, "largest sample count (quick 2048, full 4096)");
    app.add_option("--threads", threads, "worker threads (0: all)");
    app.add_option("--only", only,
                   "sampler labels to run (default: all); with --parts scenes a sampler shard: it replaces only "
                   "these samplers' rows of the scene and reuses the scene's reference when the settings match");
    app.add_option("--rqmc-log2n", rqmcLog2, "RQMC reference: log2 of points per replicate (16)");
    app.add_option("--rqmc-reps", rqmcReps, "RQMC reference: replicates (64)");
    app.add_option("--out-dir", outDir, "output folder for CSVs, slopes.md and plots (docs/study)");
    app.add_option("--study-md", studyMd, "summary markdown (docs/STUDY.md); empty: none");
    std::vector<std::string> parts = {"analytic", "pairs", "progressive", "spectra", "cost", "scenes", "scene-costs"}, sceneNames;
    std::uint32_t costRounds = 3;
    std::string scenesDir = "scenes";
    std::uint32_t sceneWidth = 0, sceneMaxSpp = 0, sceneMinTrials = 0, sceneMaxTrials = 0, referenceSpp = 0;
    std::int64_t scenePaperSpp = -1, sceneRarePixels = -1;
    std::uint32_t sceneMaxRareRenders = 0;
    double sceneRelSe = 0.1, sceneExtraSeconds = -1;
    app.add_option("--cost-rounds", costRounds, "scene-costs: rounds of every (sampler, spp) point (3)")
        ->check(CLI::Range(3u, 1000u));
    std::vector<std::string> costDevices = {"gpu", "cpu"};
    app.add_option("--cost-devices", costDevices,
                   "scene-costs: the devices to time each scene on, one run each: gpu (the Vulkan tracer) and/or cpu "
                   "(the CPU twin, as oas-render --device cpu) (default: both)")
        ->check(CLI::IsMember({"gpu", "cpu"}));
    app.add_option(
           "--parts", parts,
           "parts to run: analytic pairs progressive spectra cost scenes scene-costs (default: all; scene-costs "
           "times the measured scene points in one run per scene, --scene to choose), or none (only reassemble "
           "the scene section from its data files, STUDY.md, and redraw); STUDY.md is assembled from every part's section in the "
           "output folder")
        ->check(CLI::IsMember({"analytic", "pairs", "progressive", "spectra", "cost", "scenes", "scene-costs", "none"}));
    app.add_option("--scenes-dir", scenesDir, "scene folder (scenes)");
    app.add_option("--scene", sceneNames, "scenes to study (default: cornell7d blue_spheres9d interior_deep)");
    app.add_option("--scene-width", sceneWidth, "scene render width (quick 32, full 64)")->check(CLI::Range(8u, 1024u));
    app.add_option("--scene-max-spp", sceneMaxSpp, "largest spp of the scene ladders (quick 256, full 1024)")
        ->check(CLI::Range(128u, 65536u));
    app.add_option("--scene-paper-spp", scenePaperSpp,
                   "the 7D and 9D scenes also render every sampler at its count nearest this, the paper's 3969/4096 "
                   "(0: none; quick 0, full 4096)")
        ->check(CLI::Range(0, 65536));
    app.add_option("--scene-min-trials", sceneMinTrials, "fewest independent renders per (sampler, spp) (quick 3, full 6)")
        ->check(CLI::Range(2u, 4096u));
    app.add_option("--scene-max-trials", sceneMaxTrials,
                   "most renders per (sampler, spp) while the s.e. is above --scene-rel-se of the mean (quick 4, full 256)")
        ->check(CLI::Range(2u, 4096u));
    app.add_option("--scene-extra-seconds", sceneExtraSeconds,
                   "render seconds per scene beyond the minimum renders, shared by its points where they shrink "
                   "the s.e. most (quick 0, full 1800); a sampler shard (--only) gets its samplers' share")
        ->check(CLI::Range(0.0, 1e6));
    app.add_option("--scene-rel-se", sceneRelSe, "target standard error ÷ mean of every scene relMSE (0.1)")
        ->check(CLI::Range(0.001, 1.0));
    app.add_option("--scene-rare-pixels", sceneRarePixels,
                   "pixels per scene whose share of the relMSE is estimated apart, from many renders of just those "
                   "pixels on the CPU (default: cornell7d 4, its light's corners; the others 0)")
        ->check(CLI::Range(0, 4096));
    app.add_option("--scene-max-rare-renders", sceneMaxRareRenders,
                   "most renders of the rare pixels per point (quick 1024, full 16384)")
        ->check(CLI::Range(32u, 1u << 20));
    app.add_option("--reference-spp", referenceSpp,
                   "scene reference spp (default: the smallest power of two from 256 that is at least 16 x the scene's largest "
                   "count, at most 2^24; STUDY.md states the ratio)")
        ->check(CLI::Range(256u, 1u << 24));
    app.add_flag("--scene-top-up", sceneTopUp,
                 "add renders to the chosen scenes' earlier measurements (same settings and reference; a larger "
                 "--scene-max-trials or budget is allowed) where a point's s.e. is still above the target, "
                 "instead of measuring them again");
    std::string sceneRenderCost = "measured";
    bool sceneJoin = false;
    std::vector<std::string> mergeShards;
    app.add_option("--scene-render-cost", sceneRenderCost,
                   "what a render costs the extra budget: its measured seconds, or its point's seconds in the "
                   "scene's cost run (scene_costs.csv), so that the renders made depend on the settings alone "
                   "(measured)")
        ->check(CLI::IsMember({"measured", "cost-run"}));
    std::string rebuildReference;
    app.add_option("--scene-rebuild-reference", rebuildReference,
                   "with --only: where a scene's kept reference image is missing, render it again with this sampler "
                   "(the record's count and seeds) and join only if it is the same image (its error estimate equal "
                   "to 9 digits)");
    app.add_flag("--scene-join", sceneJoin,
                 "with --only: a sampler shard that must join the scene's kept record and reference (an error "
                 "instead of starting the scene over)");
    app.add_option("--merge-scene-shards", mergeShards,
                   "BASE SHARD...: merge sampler shards run against the base folder (scripts/study_cluster.py) "
                   "into --out-dir, then reassemble (use with --parts none)")
        ->expected(2, 1 << 20);
    std::string mergeCommand;
    app.add_option("--merge-command", mergeCommand,
                   "with --merge-scene-shards: the command recorded in the merged scenes' records (the driver's)");
    bool listSceneSamplers = false;
    app.add_flag("--list-scene-samplers", listSceneSamplers,
                 "print the labels of the samplers the scene part would run (after --quick and --only), one per line, and exit");
    app.add_flag("--no-plot", noPlot, "do not run study/plot.py afterwards");
    return oas::runCli("oas-study", app, argc, argv, [&] {
        const bool trialsGiven = trials != 0;
        if (trials == 0) trials = quick ? 512 : 4096;
        if (maxSpp == 0) maxSpp = quick ? 2048 : 4096;
        if (dimsList.empty()) dimsList = quick ? std::vector<std::uint32_t>{4, 8} : std::vector<std::uint32_t>{4, 8, 16};
        if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
        std::string command = "oas-study";
        for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];

        auto wants = [&](const std::string& part) { return std::find(parts.begin(), parts.end(), part) != parts.end(); };
        const auto t0 = std::chrono::steady_clock::now();
        std::filesystem::create_directories(outDir);
        if (sceneTopUp && (!wants("scenes") || parts.size() != 1))
            throw std::invalid_argument("--scene-top-up adds renders to the scene part alone: use --parts scenes");
        auto samplers = studySamplers();
        if (!only.empty()) {
            for (const auto& label : only)
                if (std::none_of(samplers.begin(), samplers.end(), [&](const SamplerSpec& s) { return s.label == label; })) {
                    std::string valid;
                    for (const auto& s : samplers) valid += (valid.empty() ? "" : ", ") + s.label;
                    throw std::invalid_argument("--only: \"" + label + "\" is not a sampler label (valid: " + valid + ")");
                }
            std::vector<SamplerSpec> keep;
            for (auto& s : samplers)
                if (std::find(only.begin(), only.end(), s.label) != only.end()) keep.push_back(s);
            samplers = keep;
        }
        if (listSceneSamplers) {
            for (const auto& s : sceneSamplersOf(samplers, quick)) std::printf("%s\n", s.label.c_str());
            return 0;
        }

        // 2D projections for scatter plots: the same samplers and pairs as the spectra.
        auto runProjections = [&]() {
            CsvTable pts({"sampler", "pattern", "N", "pair", "dim_a", "dim_b", "i", "x", "y"});
            const auto all = studySamplers();
            for (auto& [label, N] : projectionSamplers()) {
                auto it = std::find_if(all.begin(), all.end(), [&](auto& s) { return s.label == label; });
                if (it == all.end()) continue;
                try {
                    const oas::Pattern pat = oas::makePattern(patternRequest(*it, N, kProjectionDims));
                    const std::uint32_t seed = oas::pixelSeed(0, 0, kProjectionSeed);
                    for (const auto& pair : projectionPairs(*it, pat))
                        for (std::uint32_t i = 0; i < N; ++i)
                            pts.add({label, oas::describe(pat), std::to_string(N), pair.name, std::to_string(pair.a),
                                     std::to_string(pair.b), std::to_string(i), fmtG(oas::sample(pat, seed, i, pair.a), 9),
                                     fmtG(oas::sample(pat, seed, i, pair.b), 9)});
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "points: skip %s: %s\n", label.c_str(), e.what());
                }
            }
            pts.write(outDir + "/points.csv");
        };

        std::unique_ptr<oas::vk::Context> vulkan;  // made on first use: the analytic part needs none
        auto device = [&]() -> oas::vk::Context& {
            if (!vulkan) {
                oas::vk::selectLavapipeIfUnset();
                vulkan = std::make_unique<oas::vk::Context>();
            }
            return *vulkan;
        };
        if (wants("analytic")) {
            AnalyticOptions ao;
            ao.dims = dimsList;
            ao.trials = trials;
            ao.minSpp = minSpp;
            ao.maxSpp = maxSpp;
            ao.rqmcLog2 = rqmcLog2;
            ao.rqmcReps = rqmcReps;
            ao.threads = threads;
            ao.outDir = outDir;
            ao.studyMd = studyMd;
            ao.command = command;
            ao.quick = quick;
            ao.start = t0;
            runAnalyticStudy(ao, samplers);
        }
        if (wants("pairs")) {
            PairStudyOptions po;
            po.trials = quick ? 1024 : 4096;
            po.threads = threads;
            po.outDir = outDir;
            po.command = command;
            po.quick = quick;
            writeSection(outDir + "/pairs.md", stamped(runPairStudy(po)));
        }
        if (wants("progressive")) {
            ProgressiveOptions po;
            // 16384 in full mode (3 min on 2 cores): at N = q^2 the Faure sequence and a Bose array
            // differ by 6-9% on some integrands, which 2048 randomizations leave within noise.
            po.trials = trialsGiven ? trials : quick ? 256 : 16384;
            po.maxSpp = quick ? 1024 : 4096;
            po.threads = threads;
            po.outDir = outDir;
            po.command = command;
            po.quick = quick;
            writeSection(outDir + "/progressive.md", stamped(runProgressiveStudy(po)));
        }
        if (wants("spectra")) {
            runProjections();
            const auto ts = std::chrono::steady_clock::now();
            writeSpectra(outDir, quick ? 16 : 64, quick ? 16 : 20, threads);
            writeSection(outDir + "/spectra.md",
                         stamped(spectraSection(command, quick,
                                                std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count())));
        }
        if (wants("cost")) {
            CostOptions co;
            co.outDir = outDir;
            co.command = command;
            co.quick = quick;
            if (quick) co.pixels = 4096, co.repeats = 1;
            writeSection(outDir + "/cost.md", stamped(runCostStudy(co, samplers, device())));
        }
        if (wants("scenes")) {
            SceneStudyOptions so;
            so.outDir = outDir;
            so.command = command;
            so.quick = quick;
            so.date = today();
            so.machine = cpuModel() + " (" + std::to_string(std::thread::hardware_concurrency()) + " threads)";
            // Choosing scenes (--scene, a shard) keeps the full mode: each scene's record carries its own
            // mode, and the section says "full mode for every scene" only when every record does.
            const bool customScenes = sceneWidth || sceneMaxSpp || sceneMinTrials || sceneMaxTrials || referenceSpp ||
                                      scenePaperSpp >= 0 || sceneExtraSeconds >= 0 || sceneRarePixels >= 0 || sceneMaxRareRenders;
            so.modeLabel = quick ? "quick mode" : customScenes ? "reduced settings: see the command" : "full mode";
            so.scenesDir = scenesDir;
            so.scenes = sceneNames;
            so.width = sceneWidth ? sceneWidth : (quick ? 32 : 64);
            so.maxSpp = sceneMaxSpp ? sceneMaxSpp : (quick ? 256 : 1024);
            so.referenceSpp = referenceSpp;  // 0: a power of two >= 16 x the scene's largest count
            so.paperHighSpp = std::uint32_t(scenePaperSpp >= 0 ? scenePaperSpp : (quick ? 0 : 4096));
            // Adaptive n per point (see SceneStudyOptions): quick mode keeps a small cap so that it
            // stays at minutes; the cap is marked wherever it is hit.
            so.minTrials = sceneMinTrials ? sceneMinTrials : (quick ? 3 : 6);
            so.maxTrials = std::max(so.minTrials, sceneMaxTrials ? sceneMaxTrials : (quick ? 4u : 256u));
            so.relSeTarget = sceneRelSe;
            // Full mode: up to 1800 s of extra renders per scene, where they shrink the error bars most;
            // they stop once every point meets the target. cornell7d's points at 4096 spp need ~500 s
            // each beyond 6 renders, and its 16-49 spp points over 64 renders (2026-12-02 data).
            so.extraSecondsPerScene = sceneExtraSeconds >= 0 ? sceneExtraSeconds : (quick ? 0 : kFullExtraSeconds);
            // Sampler shards (--only): each shard joins the scene's earlier record when the settings
            // match. The extra budget (the default or the one given) is split by the shard's share of
            // the samplers, so that a scene's shards together spend the scene's budget.
            so.samplerShard = !only.empty();
            so.shardTakesKeptSettings = so.samplerShard && !customScenes;
            so.rebuildReferenceWith = rebuildReference;
            if (!rebuildReference.empty() && !so.samplerShard)
                throw std::invalid_argument("--scene-rebuild-reference: valid only with --only (a sampler shard)");
            so.topUp = sceneTopUp;
            so.costRunCosts = sceneRenderCost == "cost-run";
            so.mustJoin = sceneJoin;
            if (sceneJoin && only.empty()) throw std::invalid_argument("--scene-join: valid only with --only (a sampler shard)");
            so.rarePixels = sceneRarePixels;
            so.maxRareRenders = sceneMaxRareRenders ? sceneMaxRareRenders : (quick ? 1024u : 16384u);
            const auto sceneSamplers = sceneSamplersOf(samplers, quick);
            so.modeSamplers = sceneSamplersOf(studySamplers(), quick);
            if (so.samplerShard)
                so.extraSecondsPerScene *= double(sceneSamplers.size()) / double(so.modeSamplers.size());
            writeSection(outDir + "/scenes.md", runSceneStudy(so, sceneSamplers, device()));
        }
        if (wants("scene-costs")) {
            // One cost run per scene: every point the accuracy part measured, timed in alternating
            // rounds on this machine (scene_costs.hpp); the scene's earlier cost rows are replaced.
            const std::string refPath = outDir + "/scene_references.csv", csvPath = outDir + "/scenes.csv",
                              costPath = outDir + "/scene_costs.csv", buildPath = outDir + "/scene_cost_builds.csv";
            if (!std::filesystem::exists(refPath) || !std::filesystem::exists(csvPath))
                throw std::invalid_argument("--parts scene-costs times the points of measured scenes, and " + refPath + " or " +
                                            csvPath + " is missing: run --parts scenes first");
            const auto records = readSceneRecords(refPath);
            const auto measurements = readSceneMeasurements(csvPath);
            SceneCostOptions co;
            co.scenesDir = scenesDir;
            co.rounds = costRounds;
            co.date = today();
            co.commit = sourceCommit();
            co.machine = cpuModel() + " (" + std::to_string(std::thread::hardware_concurrency()) + " threads)";
            co.cpuThreads = threads;
            std::vector<SceneCost> fresh;
            // Pipeline builds per cost run; the rows of scenes not rerun now are kept, as in scene_costs.csv.
            CsvTable builds({"scene", "run_id", "pipelines_seconds"});
            if (std::filesystem::exists(buildPath)) {
                const CsvRows old = readCsv(buildPath);
                const size_t sceneColumn = old.column("scene", buildPath);
                for (const auto& row : old.rows)
                    if (!sceneNames.empty() &&
                        std::find(sceneNames.begin(), sceneNames.end(), row[sceneColumn]) == sceneNames.end())
                        builds.add(row);
            }
            for (const auto& record : records) {
                if (!sceneNames.empty() && std::find(sceneNames.begin(), sceneNames.end(), record.name) == sceneNames.end())
                    continue;
                for (const auto& deviceName : costDevices) {
                    co.device = deviceName == "cpu" ? CostDevice::CpuTwin : CostDevice::Gpu;
                    co.runId = record.name + (deviceName == "cpu" ? "-cpu-" : "-") + timestamp();
                    double pipelineSeconds = 0;
                    const auto rows = measureSceneCosts(record, measurements, studySamplers(), co,
                                                        co.device == CostDevice::Gpu ? &device() : nullptr,
                                                        &pipelineSeconds);
                    fresh.insert(fresh.end(), rows.begin(), rows.end());
                    if (co.device == CostDevice::Gpu) builds.add({record.name, co.runId, fmtG(pipelineSeconds, 4)});
                }
            }
            if (fresh.empty()) throw std::invalid_argument("--scene: none of the given scenes has measurements in " + csvPath);
            const auto kept = std::filesystem::exists(costPath) ? readSceneCosts(costPath) : std::vector<SceneCost>{};
            writeSceneCosts(costPath, mergeSceneCosts(kept, fresh));
            builds.write(buildPath);
            writeSection(outDir + "/scenes.md", sceneSectionFromFiles(outDir, samplers));
        }
        // Reassembling: the scene section again from its data files (e.g. after merging shards by
        // hand, or after a change to the tables); the other parts' sections are kept as they are.
        if (!mergeShards.empty()) {
            if (!wants("none") || parts.size() != 1)
                throw std::invalid_argument("--merge-scene-shards: valid only with --parts none");
            for (const auto& dir : mergeShards)
                if (!std::filesystem::is_directory(dir))
                    throw std::invalid_argument("--merge-scene-shards: " + dir + " is not a folder");
            const std::vector<std::string> shardDirs(mergeShards.begin() + 1, mergeShards.end());
            writeSection(outDir + "/scenes.md", mergeSceneShards(outDir, mergeShards.front(), shardDirs, samplers, mergeCommand));
        } else if (wants("none")) {
            const std::string section = sceneSectionFromFiles(outDir, samplers);
            if (!section.empty()) writeSection(outDir + "/scenes.md", section);
        }
        if (!studyMd.empty()) assembleStudy(studyMd, outDir);

#ifdef OAS_STUDY_PLOT_SCRIPT
        if (!noPlot) {
            // Debian's interpreter first (python3-matplotlib), whatever python3 is on PATH otherwise.
            const std::string py = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
            const std::string cmd = py + " " + OAS_STUDY_PLOT_SCRIPT + " '" + outDir + "'";
            if (std::system(cmd.c_str()) != 0)
                std::fprintf(stderr, "note: plotting skipped or failed (needs python3-matplotlib): %s\n", cmd.c_str());
        }
#endif
        return 0;
    });
}
