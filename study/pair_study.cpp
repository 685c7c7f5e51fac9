#include "pair_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <sstream>
#include <thread>

#include "integrands.hpp"
#include "oas/pattern.hpp"
#include "stats.hpp"

namespace oas::study {
namespace {

// The six column pairs of a 4D block: Bose's CMJ offsets pair columns (0,1) and (2,3).
constexpr int kPairs[6][2] = {{0, 1}, {2, 3}, {0, 2}, {0, 3}, {1, 2}, {1, 3}};
constexpr int kPartnerPairs = 2;

bool isPrime(std::uint32_t n)
{
    if (n < 2) return false;
    for (std::uint32_t d = 2; d * d <= n; ++d)
        if (n % d == 0) return false;
    return true;
}

// Two integrands per pair: the 2-additive Gaussian's term g(||(x, y)||) (smooth, not periodic:
// measured from the origin), and a smooth periodic one, exp(sin(2 pi (x + 2y)) / 2 + cos(2 pi x) / 2),
// on which shifting a whole row of cells by the same offset costs nothing at the boundary.
constexpr int kIntegrands = 2;
constexpr int kValues = 6 * kIntegrands;  // per trial: [integrand][pair]

double periodic(double x, double y)
{
    return std::exp(0.5 * std::sin(2 * kPi * (x + 2 * y)) + 0.5 * std::cos(2 * kPi * x));
}

/// The periodic integrand's integral: the trapezoid rule on an m x m grid is exact to rounding for
/// a smooth periodic function once m exceeds its bandwidth (error ~ e^-m here).
double periodicReference()
{
    const int m = 256;
    double s = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) s += periodic(double(i) / m, double(j) / m);
    return s / (double(m) * m);
}

/// Per-trial estimates of the six pair integrals of each integrand, from points[N x 4].
void pairEstimates(const double* x, std::uint32_t n, double* est)
{
    double acc[kValues] = {};
    for (std::uint32_t i = 0; i < n; ++i) {
        const double* p = x + size_t(i) * 4;
        for (int k = 0; k < 6; ++k) {
            const double a = p[kPairs[k][0]], b = p[kPairs[k][1]];
            acc[k] += kernel(Kernel::Gaussian, std::hypot(a, b));
            acc[6 + k] += periodic(a, b);
        }
    }
    for (int k = 0; k < kValues; ++k) est[k] = acc[k] / n;
}

/// MSE (and its standard error) of each pair and of their sum for integrand `f`, from trials x
/// kValues estimates.
PairMse summarize(const std::string& variant, int f, std::uint32_t q, const std::vector<double>& est, std::uint32_t trials,
                  double reference)
{
    PairMse r;
    r.variant = variant;
    r.integrand = f;
    r.q = q;
    r.n = q * q;
    auto mseOf = [&](auto errorOf) {
        double m = 0, m2 = 0;
        for (std::uint32_t t = 0; t < trials; ++t) {
            const double e = errorOf(t), d2 = e * e;
            m += d2;
            m2 += d2 * d2;
        }
        m /= trials;
        const double se = std::sqrt(std::max(0.0, m2 / trials - m * m) / (trials - 1));
        return std::pair<double, double>{m, se};
    };
    const double* base = est.data() + 6 * f;
    for (int k = 0; k < 6; ++k) {
        const auto [m, se] = mseOf([&](std::uint32_t t) { return base[size_t(t) * kValues + k] - reference; });
        r.mse.push_back(m);
        r.mseSe.push_back(se);
    }
    const auto [m, se] = mseOf([&](std::uint32_t t) {
        double sum = 0;
        for (int k = 0; k < 6; ++k) sum += base[size_t(t) * kValues + k] - reference;
        return sum;
    });
    r.sumMse = m;
    r.sumMseSe = se;
    return r;
}

/// Runs `trials` randomizations of one variant at one q, split over threads; `fill(trial, pts)`
/// writes the q^2 x 4 points of one randomization.
template <class Fill>
std::vector<double> runTrials(std::uint32_t q, std::uint32_t trials, unsigned threads, Fill fill)
{
    std::vector<double> est(size_t(trials) * kValues);
    std::vector<std::thread> pool;
    for (unsigned w = 0; w < threads; ++w)
        pool.emplace_back([&, w] {
            std::vector<double> pts(size_t(q) * q * 4);
            for (std::uint32_t t = w; t < trials; t += threads) {
                fill(t, pts);
                pairEstimates(pts.data(), q * q, est.data() + size_t(t) * kValues);
            }
        });
    for (auto& th : pool) th.join();
    return est;
}

std::string slopeCell(const SlopeFit& f)
{
    if (!f.valid()) return "—";
    return fmtF(f.slope, 2) + " ± " + fmtF(0.5 * (f.ciHigh - f.ciLow), 2);
}

}  // namespace

void textbookBose4(std::uint32_t q, bool correlated, std::uint64_t seed, std::vector<double>& points)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto shuffled = [&] {
        std::vector<std::uint32_t> p(q);
        std::iota(p.begin(), p.end(), 0u);
        std::shuffle(p.begin(), p.end(), rng);
        return p;
    };
    std::vector<std::uint32_t> strata[4];
    std::vector<std::vector<std::uint32_t>> sub[4];  // [column][level or 0] -> permutation
    for (int c = 0; c < 4; ++c) {
        strata[c] = shuffled();
        for (std::uint32_t l = 0; l < (correlated ? 1u : q); ++l) sub[c].push_back(shuffled());
    }
    const double n = double(q) * q;
    points.resize(size_t(q) * q * 4);
    for (std::uint32_t i = 0; i < q; ++i)
        for (std::uint32_t j = 0; j < q; ++j) {
            std::uint32_t level[4];
            for (std::uint32_t c = 0; c < 4; ++c) level[c] = (i + c * j) % q;  // Bose: i + c j
            double* x = points.data() + (size_t(i) * q + j) * 4;
            for (std::uint32_t c = 0; c < 4; ++c) {
                const std::uint32_t partnerLevel = level[c ^ 1u];
                const auto& sigma = sub[c][correlated ? 0 : level[c]];
                const double v = (double(strata[c][level[c]]) * q + sigma[partnerLevel] + unit(rng)) / n;
                x[c] = std::min(v, std::nextafter(1.0, 0.0));
            }
        }
}

std::string runPairStudy(const PairStudyOptions& o)
{
    const auto t0 = std::chrono::steady_clock::now();
    const unsigned threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    const double references[kIntegrands] = {quadrature2D(Kernel::Gaussian).value, periodicReference()};
    const char* integrandNames[kIntegrands] = {"g(‖(x, y)‖), Gaussian", "periodic"};
    std::vector<std::uint32_t> qs;
    for (std::uint32_t q = 5; q <= (o.quick ? 31u : 61u); ++q)
        if (isPrime(q)) qs.push_back(q);

    struct Variant {
        std::string label;
        bool library;
        bool correlated;
    };
    // Order matters below: [0] library CMJ, [1] library MJ, [2] textbook CMJ, [3] textbook MJ.
    const std::vector<Variant> variants = {
        {"BoseCMJ (library: affine permutations)", true, true},
        {"BoseMJ (library: affine permutations)", true, false},
        {"Bose CMJ, uniform permutations (textbook)", false, true},
        {"Bose MJ, uniform permutations (textbook)", false, false},
    };
    std::vector<PairMse> rows;
    for (std::uint32_t vi = 0; vi < variants.size(); ++vi) {
        const Variant& v = variants[vi];
        for (std::uint32_t q : qs) {
            std::vector<double> est;
            if (v.library) {
                oas::PatternRequest req;
                req.sampler = "bose";
                req.offset = v.correlated ? "cmj" : "mj";
                req.spp = q * q;
                req.dims = 4;
                const oas::Pattern pat = oas::makePattern(req);
                est = runTrials(q, o.trials, threads, [&](std::uint32_t t, std::vector<double>& pts) {
                    const std::uint32_t seed = oas::pixelSeed(t, vi, 0x9A125u);
                    for (std::uint32_t s = 0; s < q * q; ++s)
                        for (std::uint32_t d = 0; d < 4; ++d) pts[size_t(s) * 4 + d] = oas::sample(pat, seed, s, d);
                });
            } else {
                est = runTrials(q, o.trials, threads, [&](std::uint32_t t, std::vector<double>& pts) {
                    textbookBose4(q, v.correlated, (std::uint64_t(vi) << 48) ^ (std::uint64_t(q) << 32) ^ t, pts);
                });
            }
            for (int f = 0; f < kIntegrands; ++f) rows.push_back(summarize(v.label, f, q, est, o.trials, references[f]));
        }
        std::fprintf(stderr, "[pairs] %s done\n", v.label.c_str());
    }

    CsvTable csv({"variant", "integrand", "q", "N", "trials", "pair", "partner_pair", "mse", "mse_se"});
    for (const auto& r : rows) {
        const std::string name = r.integrand == 0 ? "gaussian" : "periodic";
        for (int k = 0; k < 6; ++k)
            csv.add({r.variant, name, std::to_string(r.q), std::to_string(r.n), std::to_string(o.trials),
                     "(" + std::to_string(kPairs[k][0]) + "," + std::to_string(kPairs[k][1]) + ")", k < kPartnerPairs ? "1" : "0",
                     fmtG(r.mse[k]), fmtG(r.mseSe[k])});
        csv.add({r.variant, name, std::to_string(r.q), std::to_string(r.n), std::to_string(o.trials), "sum", "", fmtG(r.sumMse),
                 fmtG(r.sumMseSe)});
    }
    csv.write(o.outDir + "/pairs.csv");

    // Slopes of log MSE on log N: partner pairs (mean of their two MSEs), cross pairs (mean of
    // four), and the whole 2-additive sum (which also holds the covariances between pairs).
    struct Fits {
        SlopeFit partner, cross, sum;
        double partnerAtTop = 0, crossAtTop = 0;
    };
    Fits fits[4][kIntegrands];
    for (size_t vi = 0; vi < variants.size(); ++vi)
        for (int f = 0; f < kIntegrands; ++f) {
            std::vector<double> n, partner, cross, sum;
            for (const auto& r : rows)
                if (r.variant == variants[vi].label && r.integrand == f) {
                    n.push_back(r.n);
                    partner.push_back((r.mse[0] + r.mse[1]) / 2);
                    cross.push_back((r.mse[2] + r.mse[3] + r.mse[4] + r.mse[5]) / 4);
                    sum.push_back(r.sumMse);
                }
            fits[vi][f] = {fitLogLog(n, partner), fitLogLog(n, cross), fitLogLog(n, sum), partner.back(), cross.back()};
        }
    const std::uint32_t nTop = qs.back() * qs.back();
    auto overlap = [](const SlopeFit& a, const SlopeFit& b) { return a.ciLow <= b.ciHigh && b.ciLow <= a.ciHigh; };
    // "shallower": a's slope is above b's beyond both intervals.
    auto shallower = [](const SlopeFit& a, const SlopeFit& b) { return a.ciLow > b.ciHigh; };
    const Fits& cmj = fits[0][0];
    const Fits& mj = fits[1][0];
    const bool randomizationSame = overlap(fits[0][0].partner, fits[2][0].partner) &&
                                   overlap(fits[0][0].cross, fits[2][0].cross) &&
                                   overlap(fits[1][0].partner, fits[3][0].partner) && overlap(fits[1][0].cross, fits[3][0].cross);
    const bool partnerLoss = shallower(cmj.partner, mj.partner);
    const bool crossLoss = shallower(cmj.cross, mj.cross);
    const bool periodicRecovers = !shallower(fits[0][1].partner, fits[1][1].partner);

    std::ostringstream md;
    md << "## Why BoseCMJ's 2-additive Gaussian slope is −1.6 and BoseMJ's −2\n\n"
       << "- Command: `" << o.command << "`; run time "
       << fmtF(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0) << " s (CPU)\n"
       << "- A 4D Bose pattern at prime q = " << qs.front() << " … " << qs.back() << " (N = q², " << qs.size() << " counts), "
       << o.trials << " independent randomizations per count. Each of the six 2D projections is "
       << "integrated on its own, with two integrands: the 2-additive Gaussian's term g(‖(x_a, x_b)‖) (smooth; "
       << "radius from the origin, so not periodic; reference by quadrature) and a smooth *periodic* one, "
       << "exp(sin(2π(x + 2y))/2 + cos(2πx)/2) (reference: the 256² trapezoid rule, exact to rounding for it).\n"
       << "- Bose's CMJ offsets pair columns (0,1) and (2,3): a column's substratum is a permutation of its "
       << "*partner's* level, one permutation shared by all its strata (MJ: one per stratum). In a partner pair "
       << "that is Kensler's correlated multi-jitter: the point of cell (X, Y) lies at x = (X + (τ(Y) + u)/q)/q, "
       << "so every cell of row Y has the same sub-offset in x. The *cross pairs* (0,2), (0,3), (1,2), (1,3) "
       << "take their substrata from a third column.\n"
       << "- Variants: the library's samplers (prime-field levels and substrata permuted by affine maps "
       << "x → ax + b mod q) and a textbook randomization of the same array that draws every permutation "
       << "uniformly (`std::shuffle`), written independently in `study/pair_study.cpp`.\n"
       << "- Data: [`pairs.csv`](study/pairs.csv) (every pair at every count, with standard errors). Slopes of "
       << "log MSE on log N ± the 95% half-width, as in the analytic part; MSE at N = " << nTop << ".\n\n"
       << "| variant | integrand | partner pairs: slope | cross pairs: slope | sum of the six: slope | partner MSE | "
          "cross MSE |\n|---|---|---|---|---|---|---|\n";
    for (int f = 0; f < kIntegrands; ++f)
        for (size_t i = 0; i < variants.size(); ++i)
            md << "| " << variants[i].label << " | " << integrandNames[f] << " | " << slopeCell(fits[i][f].partner) << " | "
               << slopeCell(fits[i][f].cross) << " | " << slopeCell(fits[i][f].sum) << " | " << fmtG(fits[i][f].partnerAtTop, 3)
               << " | " << fmtG(fits[i][f].crossAtTop, 3) << " |\n";
    md << "\nWhat the measurement says:\n\n"
       << "- **Not our randomization.** "
       << (randomizationSame ? "The library's affine permutations and the textbook's uniform ones give the same slopes "
                               "within their intervals, for CMJ and for MJ, on both kinds of pair (the pair argument "
                               "in DESIGN-NOTES predicts it: the variance depends only on how each permutation moves "
                               "pairs of levels)."
                             : "**The library and the textbook randomization differ** (intervals do not overlap): the "
                               "randomization matters here; see `pairs.csv`.")
       << "\n- **Not the construction.** All four rows are the same array, OA(q², 4, q, 2); only the offsets change.\n"
       << "- **The correlated offsets, on the partner pairs";
    if (partnerLoss && !crossLoss) {
        md << ".** CMJ's partner pairs converge at " << slopeCell(cmj.partner) << " against MJ's " << slopeCell(mj.partner)
           << " (MSE " << fmtF(cmj.partnerAtTop / mj.partnerAtTop, 1) << "× MJ's at N = " << nTop
           << "), while its cross pairs are no worse (" << slopeCell(cmj.cross) << " against " << slopeCell(mj.cross) << ", MSE "
           << fmtF(cmj.crossAtTop / mj.crossAtTop, 2) << "× MJ's). "
           << "The partner pairs dominate the sum, hence the −1.6 of the analytic table. Why: a sub-offset shared "
              "by a whole row of cells moves the row as one. Independent per-cell offsets (MJ) make N independent "
              "first-order errors of size ~ 1/(N q) each: MSE ~ N·(1/(N q))² = N^-2. A common shift δ_Y ~ 1/q of "
              "row Y instead adds its cells' errors coherently, and the sum of ∂f/∂x along the row telescopes to "
              "the edge difference: the row's error is ~ (q/N)·δ_Y·(f(1, y) − f(0, y)) ~ 1/N, and q rows with "
              "independent τ(Y) give MSE ~ q/N² = N^-1.5 unless f takes the same values on opposite edges. "
           << (periodicRecovers ? "The periodic integrand confirms it: there f(1, y) = f(0, y), and CMJ's partner pairs "
                                  "converge at " +
                                      slopeCell(fits[0][1].partner) + " (MJ " + slopeCell(fits[1][1].partner) + ")."
                                : "The periodic integrand does **not** confirm it (CMJ's partner pairs are still "
                                  "shallower there: " +
                                      slopeCell(fits[0][1].partner) + " against " + slopeCell(fits[1][1].partner) +
                                      "); the explanation is incomplete.")
           << "\n- **For users.** CMJ is the offset the paper pairs with Bose and the one Kensler designed for 2D "
              "pairs; it wins where the integrand over a partner pair's square is periodic (above: "
           << fmtF(fits[1][1].partnerAtTop / fits[0][1].partnerAtTop, 0) << "× lower MSE than MJ at N = " << nTop
           << ") and loses where it differs between opposite edges, as most rendering integrands do (a light's "
              "footprint, a pixel filter's support). Prefer MJ offsets for smooth, non-periodic pairs.\n";
    } else {
        md << "?** The expected pattern (partner pairs shallower with CMJ, cross pairs not) is not what this run "
              "measured: partner "
           << slopeCell(cmj.partner) << " against MJ " << slopeCell(mj.partner) << ", cross " << slopeCell(cmj.cross)
           << " against " << slopeCell(mj.cross) << ". Read `pairs.csv`.\n";
    }
    return md.str();
}

}  // namespace oas::study
