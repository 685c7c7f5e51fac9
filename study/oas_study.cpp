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
#include <sstream>
#include <thread>

#include "experiment.hpp"
#include "integrands.hpp"
#include "stats.hpp"

using namespace oas::study;

namespace {

std::uint32_t mixSeed(std::uint32_t a, std::uint32_t b, std::uint32_t c)
{
    std::uint32_t h = 0x9E3779B9u * (a + 1) ^ (b * 0x85EBCA6Bu) ^ (c * 0xC2B2AE35u);
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    return h;
}

std::string cpuModel()
{
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) {
            auto p = line.find(':');
            if (p != std::string::npos) return line.substr(p + 2);
        }
    return "unknown CPU";
}

std::string today()
{
    std::time_t t = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
    return buf;
}

struct Key {
    std::uint32_t dims;
    std::string sampler, integrand;
    bool operator<(const Key& o) const
    {
        return std::tie(dims, sampler, integrand) < std::tie(o.dims, o.sampler, o.integrand);
    }
};

struct Series {
    std::vector<double> n, mse, var;
};

std::string cell(const SlopeFit& f)
{
    if (!f.valid()) return "n/a";
    return fmtF(f.slope, 2) + " ± " + fmtF(f.ciHigh - f.slope, 2);
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-study: MSE convergence slopes of OA samplers and baselines on analytic integrands"};
    bool quick = false, noPoints = false, noPlot = false;
    std::uint32_t trials = 0, minSpp = 16, maxSpp = 0, rqmcLog2 = 16, rqmcReps = 64;
    unsigned threads = 0;
    std::vector<std::uint32_t> dimsList;
    std::vector<std::string> only;
    std::string outDir = "docs/study", studyMd = "docs/STUDY.md";
    app.add_flag("--quick", quick, "fewer trials and sizes (a few minutes on 2 cores)");
    app.add_option("--trials", trials, "independent randomizations per (sampler, N) (quick 512, full 4096)");
    app.add_option("--dims", dimsList, "dimensions to study (quick: 4 8; full: 4 8 16)");
    app.add_option("--min-spp", minSpp, "smallest sample count (16)");
    app.add_option("--max-spp", maxSpp, "largest sample count (quick 2048, full 4096)");
    app.add_option("--threads", threads, "worker threads (0: all)");
    app.add_option("--only", only, "sampler labels to run (default: all)");
    app.add_option("--rqmc-log2n", rqmcLog2, "RQMC reference: log2 of points per replicate (16)");
    app.add_option("--rqmc-reps", rqmcReps, "RQMC reference: replicates (64)");
    app.add_option("--out-dir", outDir, "output folder for CSVs, slopes.md and plots (docs/study)");
    app.add_option("--study-md", studyMd, "summary markdown (docs/STUDY.md); empty: none");
    app.add_flag("--no-points", noPoints, "skip the 2D projection dump (points.csv)");
    app.add_flag("--no-plot", noPlot, "do not run study/plot.py afterwards");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (trials == 0) trials = quick ? 512 : 4096;
    if (maxSpp == 0) maxSpp = quick ? 2048 : 4096;
    if (dimsList.empty()) dimsList = quick ? std::vector<std::uint32_t>{4, 8} : std::vector<std::uint32_t>{4, 8, 16};
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    std::string command = "oas-study";
    for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];

    const auto t0 = std::chrono::steady_clock::now();
    std::filesystem::create_directories(outDir);
    auto samplers = studySamplers();
    if (!only.empty()) {
        std::vector<SamplerSpec> keep;
        for (auto& s : samplers)
            if (std::find(only.begin(), only.end(), s.label) != only.end()) keep.push_back(s);
        samplers = keep;
    }

    CsvTable csv({"dims", "integrand", "combo", "kernel", "sampler", "pattern", "N", "trials", "reference",
                  "reference_error", "mean_estimate", "mse", "mse_stderr", "variance", "rel_mse"});
    CsvTable refCsv({"dims", "integrand", "reference", "reference_error", "method", "closed_form", "rqmc", "rqmc_stderr",
                     "z_closed_vs_rqmc"});
    std::map<Key, Series> series;
    std::map<std::uint32_t, std::vector<Integrand>> integrandsByDims;
    std::map<std::string, std::pair<double, double>> refTable;  // integrand name -> (value, error)
    std::ostringstream refMd;
    std::vector<std::string> chooserNotes;

    for (std::uint32_t D : dimsList) {
        const auto fs = paperIntegrands(D);
        integrandsByDims[D] = fs;
        std::fprintf(stderr, "[%uD] references (RQMC cross-check: %u x 2^%u points)...\n", D, rqmcReps, rqmcLog2);
        const auto rq = rqmcReference(fs, D, rqmcLog2, rqmcReps, threads);
        std::vector<double> refs(fs.size()), refErr(fs.size());
        for (size_t f = 0; f < fs.size(); ++f) {
            const Reference cf = closedFormReference(fs[f]);
            const Reference use = cf.exact ? cf : rq[f];
            refs[f] = use.value;
            refErr[f] = use.error;
            const double z = cf.exact && rq[f].error > 0 ? (cf.value - rq[f].value) / rq[f].error : std::nan("");
            refCsv.add({std::to_string(D), fs[f].name(), fmtG(use.value, 17), fmtG(use.error, 3), use.method,
                        cf.exact ? fmtG(cf.value, 17) : "", fmtG(rq[f].value, 17), fmtG(rq[f].error, 3),
                        std::isnan(z) ? "" : fmtF(z, 2)});
            refMd << "| " << fs[f].name() << " | " << fmtG(use.value, 12) << " | " << fmtG(use.error, 2) << " | "
                  << use.method << " | " << fmtG(rq[f].value, 10) << " ± " << fmtG(rq[f].error, 2) << " | "
                  << (std::isnan(z) ? "—" : fmtF(z, 2)) << " |\n";
        }
        for (size_t si = 0; si < samplers.size(); ++si) {
            const auto& spec = samplers[si];
            const auto ladder = countLadder(spec, D, minSpp, maxSpp);
            const auto ts = std::chrono::steady_clock::now();
            for (std::uint32_t N : ladder) {
                oas::Pattern pat;
                std::string desc;
                try {
                    pat = oas::makePattern(patternRequest(spec, N, D));
                    desc = oas::describe(pat);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "  skip %s N=%u: %s\n", spec.label.c_str(), N, e.what());
                    continue;
                }
                if (spec.sampler == "oa" && pat.blockDims < D)
                    chooserNotes.push_back(std::to_string(D) + "D, N=" + std::to_string(N) + ": the chooser picked `" + desc +
                                           "`, whose blocks hold fewer than " + std::to_string(D) +
                                           " dims, so pairs across blocks are not stratified (padding)");
                const auto st = measure(pat, fs, refs, D, N, trials, mixSeed(std::uint32_t(si), D, N), threads);
                for (size_t f = 0; f < fs.size(); ++f) {
                    const double rel = refs[f] != 0 ? st[f].mse / (refs[f] * refs[f]) : std::nan("");
                    csv.add({std::to_string(D), fs[f].name(), comboName(fs[f].combo), kernelName(fs[f].kernel),
                             spec.label, desc, std::to_string(N), std::to_string(trials), fmtG(refs[f], 17),
                             fmtG(refErr[f], 3), fmtG(st[f].mean, 17), fmtG(st[f].mse, 6), fmtG(st[f].mseStderr, 3),
                             fmtG(st[f].variance, 6), fmtG(rel, 6)});
                    auto& s = series[{D, spec.label, fs[f].name()}];
                    s.n.push_back(N);
                    s.mse.push_back(st[f].mse);
                    s.var.push_back(st[f].variance);
                }
            }
            const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
            std::string ns;
            for (auto n : ladder) {
                ns += ' ';
                ns += std::to_string(n);
            }
            std::fprintf(stderr, "  [%uD] %-22s %5.1f s  N:%s\n", D, spec.label.c_str(), secs, ns.c_str());
        }
    }
    csv.write(outDir + "/analytic.csv");
    refCsv.write(outDir + "/references.csv");

    // Slope fits.
    CsvTable slopeCsv({"dims", "integrand", "sampler", "slope", "ci_low", "ci_high", "stderr", "points", "n_min",
                       "n_max", "r2", "variance_slope"});
    std::map<Key, SlopeFit> fits;
    for (auto& [k, s] : series) {
        const SlopeFit f = fitLogLog(s.n, s.mse);
        const SlopeFit fv = fitLogLog(s.n, s.var);
        fits[k] = f;
        slopeCsv.add({std::to_string(k.dims), k.integrand, k.sampler, fmtF(f.slope, 4), fmtF(f.ciLow, 4),
                      fmtF(f.ciHigh, 4), fmtF(f.stderr_, 4), std::to_string(f.n),
                      std::to_string(std::uint32_t(s.n.front())), std::to_string(std::uint32_t(s.n.back())),
                      fmtF(f.r2, 4), fmtF(fv.slope, 4)});
    }
    slopeCsv.write(outDir + "/slopes.csv");

    auto fitOf = [&](std::uint32_t D, const std::string& sampler, const std::string& integrand) {
        auto it = fits.find({D, sampler, integrand});
        return it == fits.end() ? SlopeFit{} : it->second;
    };

    std::ostringstream md;
    md << "# MSE convergence slopes on the analytic integrands\n\n"
       << "Generated by `" << command << "` (" << trials << " independent randomizations per point, N in ["
       << minSpp << ", " << maxSpp << "]). Each cell: least-squares slope of log MSE vs log N ± the half-width of "
       << "its 95% confidence interval (Student t, points − 2 degrees of freedom). Every measurement is in "
       << "`analytic.csv`; fit details (points, N range, R², slope of the sample variance) in `slopes.csv`.\n\n";
    for (std::uint32_t D : dimsList) {
        const auto& fs = integrandsByDims[D];
        md << "## " << D << "D\n\n| sampler |";
        for (auto& f : fs) md << " " << comboName(f.combo) << "<br>" << kernelName(f.kernel) << " |";
        md << "\n|---|";
        for (size_t i = 0; i < fs.size(); ++i) md << "---|";
        md << "\n";
        for (auto& spec : samplers) {
            md << "| " << spec.label << " |";
            for (auto& f : fs) md << " " << cell(fitOf(D, spec.label, f.name())) << " |";
            md << "\n";
        }
        md << "\n";
    }
    {
        std::ofstream f(outDir + "/slopes.md");
        f << md.str();
    }

    // 2D projections for scatter plots.
    if (!noPoints) {
        CsvTable pts({"sampler", "pattern", "N", "pair", "dim_a", "dim_b", "i", "x", "y"});
        const std::vector<std::pair<std::string, std::uint32_t>> which = {
            {"BoseCMJ", 121}, {"BoseMJ", 121}, {"BushMJ(t=2)", 121}, {"BoseBushCMJ", 128},
            {"CMJND(t=4)", 81}, {"Random", 128}, {"CMJ2D-pad", 128}, {"Halton", 128}, {"Sobol", 128}};
        for (auto& [label, N] : which) {
            auto all = studySamplers();
            auto it = std::find_if(all.begin(), all.end(), [&](auto& s) { return s.label == label; });
            if (it == all.end()) continue;
            try {
                const oas::Pattern pat = oas::makePattern(patternRequest(*it, N, 8));
                std::uint32_t block = pat.blockDims ? pat.blockDims : 2;
                if (it->sampler == "halton") block = 32;
                if (it->sampler == "sobol") block = 64;
                if (it->sampler == "random") block = 1;
                const std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs = {
                    {0, 1}, {0, 2}, {1, 5}, {0, block}};
                const std::uint32_t seed = oas::pixelSeed(0, 0, 12345);
                for (auto [a, b] : pairs) {
                    const std::string name = (a == 0 && b == block) ? "cross-block (0," + std::to_string(b) + ")"
                                                                    : "(" + std::to_string(a) + "," + std::to_string(b) + ")";
                    for (std::uint32_t i = 0; i < N; ++i)
                        pts.add({label, oas::describe(pat), std::to_string(N), name, std::to_string(a), std::to_string(b),
                                 std::to_string(i), fmtG(oas::sample(pat, seed, i, a), 9),
                                 fmtG(oas::sample(pat, seed, i, b), 9)});
                }
            } catch (const std::exception& e) {
                std::fprintf(stderr, "points: skip %s: %s\n", label.c_str(), e.what());
            }
        }
        pts.write(outDir + "/points.csv");
    }

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    // Goal and paper comparison (4D if studied, else the first dims).
    const std::uint32_t Dg = std::find(dimsList.begin(), dimsList.end(), 4u) != dimsList.end() ? 4 : dimsList.front();
    const std::string binName = comboName(Combo::Additive2) + " " + kernelName(Kernel::BinaryStep) + " " + std::to_string(Dg) + "D";
    const std::string gauName = comboName(Combo::Additive2) + " " + kernelName(Kernel::Gaussian) + " " + std::to_string(Dg) + "D";
    bool goalMet = true, anyOa = false;
    std::ostringstream goal;
    for (auto& s : samplers) {
        if (!s.oaStrength2) continue;
        const SlopeFit f = fitOf(Dg, s.label, binName);
        if (!f.valid()) continue;
        anyOa = true;
        const bool ok = f.slope <= -1.45;
        goalMet = goalMet && ok;
        goal << "| " << s.label << " | " << cell(f) << " | [" << fmtF(f.ciLow, 2) << ", " << fmtF(f.ciHigh, 2) << "] | "
             << (ok ? "yes" : "**no**") << " |\n";
    }
    goalMet = goalMet && anyOa;
    {
        const SlopeFit f = fitOf(Dg, "OA-chooser(t=2,cmj)", binName);
        if (f.valid())
            goal << "| OA-chooser(t=2,cmj) (not counted: mixes constructions per N, see below) | " << cell(f) << " | ["
                 << fmtF(f.ciLow, 2) << ", " << fmtF(f.ciHigh, 2) << "] | " << (f.slope <= -1.45 ? "yes" : "no") << " |\n";
    }

    if (!studyMd.empty()) {
        std::filesystem::path p(studyMd);
        if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
        std::ofstream o(studyMd);
        const std::string rel = std::filesystem::relative(outDir, p.has_parent_path() ? p.parent_path() : ".").string();
        o << "# Study: MSE convergence of orthogonal-array sampling on analytic integrands\n\n"
          << "- Machine: " << cpuModel() << ", " << std::thread::hardware_concurrency() << " hardware threads ("
          << threads << " used)\n"
          << "- Date: " << today() << "\n"
          << "- Command (from the repository root): `build/" << command << "`" << (quick ? " (quick mode)" : " (full mode)")
          << "\n- Run time: " << fmtF(seconds, 1) << " s\n"
          << "- Trials (independent randomizations = pixel seeds) per (sampler, N): " << trials << "; N in [" << minSpp
          << ", " << maxSpp << "]; dimensions: ";
        for (size_t i = 0; i < dimsList.size(); ++i) o << (i ? ", " : "") << dimsList[i];
        o << "\n- Outputs: [`analytic.csv`](" << rel << "/analytic.csv) (every measurement), [`references.csv`](" << rel
          << "/references.csv), [`slopes.csv`](" << rel << "/slopes.csv), [`slopes.md`](" << rel
          << "/slopes.md) (all slope tables), [`points.csv`](" << rel << "/points.csv); figures by `python3 study/plot.py "
          << outDir << "`: `" << rel << "/mse_<D>d.png`, `" << rel << "/goal_2additive_binary.png`, `" << rel
          << "/projections.png`.\n\n";
        o << "## Goal\n\n> 2-additive binary step: MSE slope ≤ −1.45 for strength-2 OAs (padded samplers about −1.0).\n\n"
          << "**" << (goalMet ? "Met" : "Not met") << "** in " << Dg
          << "D (criterion: the fitted slope of every strength-2 OA sampler ≤ −1.45; the 95% interval is shown "
             "for honesty).\n\n| strength-2 OA | slope ± 95% | 95% CI | ≤ −1.45 |\n|---|---|---|---|\n"
          << goal.str() << "\n";
        if (!chooserNotes.empty()) {
            o << "Chooser (`oa`) findings, reported rather than fixed here (host/oas/pattern.cpp is outside this study):\n\n";
            for (auto& n : chooserNotes) o << "- " << n << ".\n";
            o << "\nThe `oa` ladder takes its counts from `validCounts(\"oa\", 2, D, ...)`, which includes every s^2 "
                 "through CMJND with d = 2; at such counts the chooser returns a padded 2-dim-block pattern, and the "
                 "MSE at that point is several times that of Bose at a nearby N, which flattens the chooser's "
                 "slope. The per-construction series above are the strength-2 OAs the goal is about.\n\n";
        }
        o << "## Side by side with the paper (" << Dg << "D)\n\n| integrand | sampler | paper | this study |\n|---|---|---|---|\n";
        auto row = [&](const std::string& integ, const std::string& label, const std::string& paper) {
            o << "| " << integ << " | " << label << " | " << paper << " | " << cell(fitOf(Dg, label, integ)) << " |\n";
        };
        for (auto l : {"BoseCMJ", "BoseMJ", "BushMJ(t=2)", "BoseBushCMJ", "AddelmanKempthorneCMJ", "OA-chooser(t=2,cmj)"})
            row(binName, l, "OA strength 2: −1.49");
        for (auto l : {"Jittered2D-pad", "CMJ2D-pad", "ZeroTwo-pad"}) row(binName, l, "padded 2D: about −1.0");
        row(binName, "Sobol", "−1.54");
        row(binName, "Random", "(−1, theory)");
        row(gauName, "BoseCMJ", "−1.52");
        row(gauName, "BushMJ(t=2)", "−1.78");
        o << "\nAll slopes (every sampler, integrand and dimension): [`slopes.md`](" << rel << "/slopes.md).\n\n";
        o << "## Method\n\n"
          << "- Integrands (DESIGN §4, after Subr et al. 2016): kernels g(r) with r_end = 3/π, r_start = r_end − 0.2, "
             "σ = 1/3: Gaussian exp(−r²/2σ²), linear step 1 − linearstep(r_start, r_end, r) (continuous, kinks at "
             "r_start and r_end), binary step [r < r_end] (discontinuous); combined as 1-additive Σ_i g(x_i), "
             "2-additive Σ_{i<j} g(‖(x_i,x_j)‖), 2-multiplicative Π_{i<j} g(‖(x_i,x_j)‖) and radial g(‖x‖).\n"
          << "- Points are **not centred**: x ∈ [0,1)^D and radii are measured from the origin (a corner of the "
             "cube), as in the paper. Since r_end < 1 the step kernels' discontinuities lie inside the cube.\n"
          << "- Estimator: the mean of f over N samples of one randomized point set; MSE = mean over trials of "
             "(estimate − reference)²; each trial is one pixel of `oas::generateCpu` (an independent pixel seed), "
             "all integrands share the point sets. Slopes: least squares of log MSE on log N over the whole "
             "ladder, 95% CI from Student t with n − 2 degrees of freedom. `slopes.csv` also gives the slope of "
             "the sample variance (no reference involved).\n"
          << "- Sample counts: OA constructions use the valid count nearest each half-octave target 16·2^(k/2) "
             "(within a factor 2^(1/4)); baselines use powers of two. CMJND uses strength 4 (in 4D the full "
             "factorial s⁴; in more dims, padded blocks of 4).\n"
          << "- Samples are floats quantized to 2^-24 (below 1); the RQMC cross-check of the smooth 1-additive "
             "Gaussian and linear-step integrands shows a bias of about 3e-8 per dimension (large z in the table "
             "below) consistent with that quantization (truncation towards 0 of a decreasing g). Its square "
             "(~1e-14) is far below every MSE measured here, so it does not affect the slopes.\n"
          << "- OA offsets: Bose CMJ and MJ, Bush (t = 2) MJ, Bose–Bush CMJ, Addelman–Kempthorne CMJ, the `oa` "
             "chooser with CMJ, CMJND CMJ.\n\n";
        o << "## Reference values\n\n"
          << "Closed forms wherever possible (1-additive: D·∫g; 2-additive: C(D,2)·I2 with I2 = I1² (Gaussian), "
             "π r_end²/4 (binary), (π/2)∫g(r) r dr (linear); 2-multiplicative Gaussian is separable; "
             "2-multiplicative binary via the two largest coordinates: (r_end/√2)^D + D r_end^D ∫_0^{π/4} sin^D θ dθ; "
             "radial: separable Gaussian, or the ball in the positive orthant). Their error is rounding (stated as "
             "1e-14 relative). The 2-additive I2 values were also checked against 40×40 Gauss-Legendre in polar "
             "coordinates (unit test). The 2-multiplicative linear step has no closed form: its reference is a "
             "randomized-QMC estimate (" << rqmcReps << " Owen-scrambled Sobol sets of 2^" << rqmcLog2
          << " points), its error the standard error. Every integrand is also estimated by that RQMC, and z is "
             "(closed form − RQMC)/SE, a check of the closed forms and of the sampler.\n\n"
          << "| integrand | reference | abs. error | method | RQMC ± SE | z |\n|---|---|---|---|---|---|\n"
          << refMd.str() << "\n";
        o << "## All slopes\n\n" << md.str().substr(md.str().find("## ")) << "\n";
    }
    std::fprintf(stderr, "done in %.1f s; goal (2-additive binary step, strength-2 OAs <= -1.45 in %uD): %s\n", seconds,
                 Dg, goalMet ? "met" : "NOT met");

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
}
