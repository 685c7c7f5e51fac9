#include "analytic_part.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <tuple>

#include "integrands.hpp"
#include "oas/pattern.hpp"
#include "section_io.hpp"
#include "stats.hpp"

namespace oas::study {
namespace {

struct Key {
    std::uint32_t dims;
    std::string sampler, integrand;
    bool operator<(const Key& o) const { return std::tie(dims, sampler, integrand) < std::tie(o.dims, o.sampler, o.integrand); }
};

struct Series {
    std::vector<double> n, mse, var, mseSe;  ///< mseSe: s.e. of each MSE over its trials
};

std::string cell(const SlopeFit& f)
{
    if (!f.valid()) return "n/a";
    return fmtF(f.slope, 2) + " ± " + fmtF(f.ciHigh - f.slope, 2);
}

}  // namespace

void runAnalyticStudy(const AnalyticOptions& opt, const std::vector<SamplerSpec>& samplers)
{
    CsvTable csv({"dims", "integrand", "combo", "kernel", "sampler", "pattern", "N", "trials", "reference", "reference_error",
                  "mean_estimate", "mse", "mse_stderr", "variance", "rel_mse"});
    CsvTable refCsv({"dims", "integrand", "reference", "reference_error", "method", "closed_form", "rqmc", "rqmc_stderr",
                     "z_closed_vs_rqmc"});
    std::map<Key, Series> series;
    std::map<std::uint32_t, std::vector<Integrand>> integrandsByDims;
    std::map<std::string, std::pair<double, double>> refTable;  // integrand name -> (value, error)
    std::ostringstream refMd;
    std::vector<std::string> chooserNotes;

    for (std::uint32_t D : opt.dims) {
        const auto fs = paperIntegrands(D);
        integrandsByDims[D] = fs;
        std::fprintf(stderr, "[%uD] references (RQMC cross-check: %u x 2^%u points)...\n", D, opt.rqmcReps, opt.rqmcLog2);
        const auto rq = rqmcReference(fs, D, opt.rqmcLog2, opt.rqmcReps, opt.threads);
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
            refMd << "| " << fs[f].name() << " | " << fmtG(use.value, 12) << " | " << fmtG(use.error, 2) << " | " << use.method
                  << " | " << fmtG(rq[f].value, 10) << " ± " << fmtG(rq[f].error, 2) << " | "
                  << (std::isnan(z) ? "—" : fmtF(z, 2)) << " |\n";
        }
        for (size_t si = 0; si < samplers.size(); ++si) {
            const auto& spec = samplers[si];
            const auto ladder = countLadder(spec, D, opt.minSpp, opt.maxSpp);
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
                const auto st = measure(pat, fs, refs, D, N, opt.trials, mixSeed(std::uint32_t(si), D, N), opt.threads);
                for (size_t f = 0; f < fs.size(); ++f) {
                    const double rel = refs[f] != 0 ? st[f].mse / (refs[f] * refs[f]) : std::nan("");
                    csv.add({std::to_string(D), fs[f].name(), comboName(fs[f].combo), kernelName(fs[f].kernel), spec.label, desc,
                             std::to_string(N), std::to_string(opt.trials), fmtG(refs[f], 17), fmtG(refErr[f], 3),
                             fmtG(st[f].mean, 17), fmtG(st[f].mse, 6), fmtG(st[f].mseStderr, 3), fmtG(st[f].variance, 6),
                             fmtG(rel, 6)});
                    auto& s = series[{D, spec.label, fs[f].name()}];
                    s.n.push_back(N);
                    s.mse.push_back(st[f].mse);
                    s.mseSe.push_back(st[f].mseStderr);
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
    csv.write(opt.outDir + "/analytic.csv");
    refCsv.write(opt.outDir + "/references.csv");

    // Slope fits.
    CsvTable slopeCsv({"dims", "integrand", "sampler", "slope", "ci_low", "ci_high", "stderr", "points", "n_min", "n_max", "r2",
                       "variance_slope"});
    std::map<Key, SlopeFit> fits;
    for (auto& [k, s] : series) {
        const SlopeFit f = fitLogLog(s.n, s.mse);
        const SlopeFit fv = fitLogLog(s.n, s.var);
        fits[k] = f;
        slopeCsv.add({std::to_string(k.dims), k.integrand, k.sampler, fmtF(f.slope, 4), fmtF(f.ciLow, 4), fmtF(f.ciHigh, 4),
                      fmtF(f.stderr_, 4), std::to_string(f.n), std::to_string(std::uint32_t(s.n.front())),
                      std::to_string(std::uint32_t(s.n.back())), fmtF(f.r2, 4), fmtF(fv.slope, 4)});
    }
    slopeCsv.write(opt.outDir + "/slopes.csv");

    auto fitOf = [&](std::uint32_t D, const std::string& sampler, const std::string& integrand) {
        auto it = fits.find({D, sampler, integrand});
        return it == fits.end() ? SlopeFit{} : it->second;
    };

    std::ostringstream md;
    md << "# MSE convergence slopes on the analytic integrands\n\n"
       << "Generated by `" << opt.command << "` (" << opt.trials << " independent randomizations per point, N in [" << opt.minSpp
       << ", " << opt.maxSpp << "]). Each cell: least-squares slope of log MSE vs log N ± the half-width of "
       << "its 95% confidence interval (Student t, points − 2 degrees of freedom). Every measurement is in "
       << "`analytic.csv`; fit details (points, N range, R², slope of the sample variance) in `slopes.csv`.\n\n";
    for (std::uint32_t D : opt.dims) {
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
        std::ofstream f(opt.outDir + "/slopes.md");
        f << md.str();
    }

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - opt.start).count();

    // Goal and paper comparison (4D if studied, else the first dims).
    const std::uint32_t Dg = std::find(opt.dims.begin(), opt.dims.end(), 4u) != opt.dims.end() ? 4 : opt.dims.front();
    const std::string binName =
        comboName(Combo::Additive2) + " " + kernelName(Kernel::BinaryStep) + " " + std::to_string(Dg) + "D";
    const std::string gauName = comboName(Combo::Additive2) + " " + kernelName(Kernel::Gaussian) + " " + std::to_string(Dg) + "D";
    bool goalMet = true, goalMissed = false, anyOa = false;
    std::ostringstream goal;
    for (auto& s : samplers) {
        if (!s.oaStrength2) continue;
        const SlopeFit f = fitOf(Dg, s.label, binName);
        if (!f.valid()) continue;
        anyOa = true;
        // The verdict rule of the whole study (stats.hpp compare): the slope counts as below −1.45
        // only where it is more than 2 s.e. below, as above only where more than 2 s.e. above.
        const Verdict v = compare(Estimate{f.slope, f.stderr_, std::uint32_t(f.n), false}, Estimate{-1.45, 0, 0, false});
        goalMet = goalMet && v == Verdict::FirstLower;
        goalMissed = goalMissed || v == Verdict::SecondLower;
        goal << "| " << s.label << " | " << cell(f) << " | [" << fmtF(f.ciLow, 2) << ", " << fmtF(f.ciHigh, 2) << "] | "
             << fmtF(f.stderr_, 3) << " | "
             << (v == Verdict::FirstLower    ? "yes"
                 : v == Verdict::SecondLower ? "**no**"
                                             : "tie")
             << " |\n";
    }
    goalMet = goalMet && anyOa;
    {
        const SlopeFit f = fitOf(Dg, "OA-chooser(t=2,cmj)", binName);
        if (f.valid())
            goal << "| OA-chooser(t=2,cmj) (not counted: mixes constructions per N, see below) | " << cell(f) << " | ["
                 << fmtF(f.ciLow, 2) << ", " << fmtF(f.ciHigh, 2) << "] | " << fmtF(f.stderr_, 3) << " | "
                 << verdictWord(compare(Estimate{f.slope, f.stderr_, std::uint32_t(f.n), false}, Estimate{-1.45, 0, 0, false}))
                 << " (lower = yes) |\n";
    }

    {
        std::filesystem::path p(opt.studyMd.empty() ? "docs/STUDY.md" : opt.studyMd);
        std::ostringstream o;
        const std::string rel = std::filesystem::relative(opt.outDir, p.has_parent_path() ? p.parent_path() : ".").string();
        o << "# Analytic integrands: MSE convergence of orthogonal-array sampling\n\n"
          << "- Machine: " << cpuModel() << ", " << std::thread::hardware_concurrency() << " hardware threads (" << opt.threads
          << " used)\n"
          << "- Date: " << today() << "\n"
          << "- Command (from the repository root): `build/" << opt.command << "`"
          << (opt.quick ? " (quick mode)" : " (full mode)") << "\n- Run time: " << fmtF(seconds, 1) << " s\n"
          << "- Trials (independent randomizations = pixel seeds) per (sampler, N): " << opt.trials << "; N in [" << opt.minSpp
          << ", " << opt.maxSpp << "]; dimensions: ";
        for (size_t i = 0; i < opt.dims.size(); ++i) o << (i ? ", " : "") << opt.dims[i];
        o << "\n- Outputs: [`analytic.csv`](" << rel << "/analytic.csv) (every measurement), [`references.csv`](" << rel
          << "/references.csv), [`slopes.csv`](" << rel << "/slopes.csv), [`slopes.md`](" << rel
          << "/slopes.md) (all slope tables), [`points.csv`](" << rel << "/points.csv); figures by `python3 study/plot.py "
          << opt.outDir << "`: `" << rel << "/mse_<D>d.png`, `" << rel << "/goal_2additive_binary.png`, `" << rel
          << "/projections.png`.\n\n";
        o << "## Goal\n\n> 2-additive binary step: MSE slope ≤ −1.45 for strength-2 OAs (padded samplers about −1.0).\n\n"
          << "**"
          << (goalMet      ? "Met"
              : goalMissed ? "Not met"
                           : "Tie (not decided by the error bars)")
          << "** in " << Dg
          << "D (criterion: the fitted slope of every strength-2 OA sampler below −1.45 by more than twice its "
             "standard error, the study's verdict rule; a slope within 2 s.e. of −1.45 is a tie, one more than "
             "2 s.e. above is a miss).\n\n| strength-2 OA | slope ± 95% | 95% CI | s.e. | ≤ −1.45 |\n|---|---|---|---|---|\n"
          << goal.str() << "\n";
        if (!chooserNotes.empty()) {
            o << "Chooser (`oa`) findings, reported rather than fixed here (host/oas/pattern.cpp is outside this study):\n\n";
            for (auto& n : chooserNotes) o << "- " << n << ".\n";
            o << "\nThe `oa` ladder takes its counts from `validCounts(\"oa\", 2, D, ...)`, which includes every s^2 "
                 "through CMJND with d = 2; at such counts the chooser returns a padded 2-dim-block pattern, and the "
                 "MSE at that point is several times that of Bose at a nearby N, which flattens the chooser's "
                 "slope. The per-construction series above are the strength-2 OAs the goal is about.\n\n";
        }
        o << "## Side by side with the paper (" << Dg
          << "D)\n\n| integrand | sampler | paper | this study |\n|---|---|---|---|\n";
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
        // Where the gain comes from and where it vanishes: a strength-2 OA stratifies every 2D
        // projection, so it helps integrands whose variance lives in 1D and 2D projections
        // (additive ones) and loses its edge where the integrand couples more dimensions than
        // the strength (multiplicative and radial kernels, growing with D).
        o << "## Where the OA gain comes from, and where it vanishes\n\n"
          << "MSE of BoseCMJ ÷ MSE of Random at the largest N both reached (Bose's valid count nearest Random's "
             "largest power of two), binary-step kernel; in brackets the two fitted slopes (BoseCMJ / Random). "
             "A strength-2 OA stratifies every 1D and 2D projection: its gain is largest on additive integrands, "
             "whose variance lives in those projections, and fades as the integrand couples more dimensions "
             "than the strength (2-multiplicative, radial) and as D grows.\n\n| integrand |";
        for (auto D : opt.dims) o << " " << D << "D |";
        o << "\n|---|";
        for (size_t i = 0; i < opt.dims.size(); ++i) o << "---|";
        o << "\n";
        for (Combo combo : {Combo::Additive1, Combo::Additive2, Combo::Multiplicative2, Combo::Radial}) {
            o << "| " << comboName(combo) << " " << kernelName(Kernel::BinaryStep) << " |";
            for (auto D : opt.dims) {
                const std::string name = comboName(combo) + " " + kernelName(Kernel::BinaryStep) + " " + std::to_string(D) + "D";
                const auto oa = series.find({D, "BoseCMJ", name});
                const auto rnd = series.find({D, "Random", name});
                if (oa == series.end() || rnd == series.end() || rnd->second.n.empty()) {
                    o << " — |";
                    continue;
                }
                const double nr = rnd->second.n.back();
                size_t best = 0;
                for (size_t i = 1; i < oa->second.n.size(); ++i)
                    if (std::abs(std::log(oa->second.n[i] / nr)) < std::abs(std::log(oa->second.n[best] / nr))) best = i;
                // Compare at equal N: scale Random's MSE (slope -1, exact for independent samples).
                const double rndAt = rnd->second.mse.back() * nr / oa->second.n[best];
                // Random's slope is exactly -1 in theory; far from it, the MSE is not resolved by
                // the trials (e.g. a 16D ball holding 1.7e-6 of the cube: almost every estimate is 0).
                const double rndSlope = fitOf(D, "Random", name).slope;
                if (!(rndSlope > -1.3 && rndSlope < -0.7)) {
                    o << " not resolved (Random's slope " << fmtF(rndSlope, 2) << ", theory −1) |";
                    continue;
                }
                // ± the delta-method s.e. of the ratio from the two MSEs' s.e. over `trials` trials each.
                const Estimate oaE{oa->second.mse[best], oa->second.mseSe[best], opt.trials, false};
                const Estimate rndE{rndAt, rnd->second.mseSe.back() * nr / oa->second.n[best], opt.trials, false};
                o << " " << fmtRatio(ratioOf(oaE, rndE), 3) << " (" << fmtF(fitOf(D, "BoseCMJ", name).slope, 2) << " / "
                  << fmtF(fitOf(D, "Random", name).slope, 2) << ") |";
            }
            o << "\n";
        }
        o << "\nRandom's MSE is scaled to Bose's N by 1/N (exact for independent samples). Each MSE is a mean over " << opt.trials
          << " trials; the ratio's ± is its first-order s.e. from the two MSEs' standard errors "
             "(`mse_stderr` in `analytic.csv`; the MSE plots show ± 1 s.e.).\n\n";
        o << "## Method\n\n"
          << "- Integrands (after Subr et al. 2016, as used by Jarosz et al. 2019): kernels g(r) with r_end = 3/π, r_start = "
             "r_end − 0.2, "
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
             "randomized-QMC estimate ("
          << opt.rqmcReps << " Owen-scrambled Sobol sets of 2^" << opt.rqmcLog2
          << " points), its error the standard error. Every integrand is also estimated by that RQMC, and z is "
             "(closed form − RQMC)/SE, a check of the closed forms and of the sampler.\n\n"
          << "| integrand | reference | abs. error | method | RQMC ± SE | z |\n|---|---|---|---|---|---|\n"
          << refMd.str() << "\n";
        o << "## All slopes\n\n" << md.str().substr(md.str().find("## ")) << "\n";
        writeSection(opt.outDir + "/analytic.md", demoteHeadings(o.str()));
    }
    std::fprintf(stderr, "done in %.1f s; goal (2-additive binary step, strength-2 OAs <= -1.45 in %uD): %s\n", seconds, Dg,
                 goalMet      ? "met"
                 : goalMissed ? "NOT met"
                              : "tie (within 2 s.e.)");
}

}  // namespace oas::study
