#include "experiment.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace oas::study {

std::vector<SamplerSpec> studySamplers()
{
    return {
        {"BoseCMJ", "bose", "cmj", 2, true, false},
        {"BoseMJ", "bose", "mj", 2, true, false},
        {"BushMJ(t=2)", "bush", "mj", 2, true, false},
        {"BoseBushCMJ", "bose-bush", "cmj", 2, true, false},
        {"AddelmanKempthorneCMJ", "addelman-kempthorne", "cmj", 2, true, false},
        {"OA-chooser(t=2,cmj)", "oa", "cmj", 2, false, false},
        {"CMJND(t=4)", "cmjnd", "cmj", 4, false, false},
        {"Random", "random", "cmj", 0, false, true},
        {"Jittered2D-pad", "jittered2d", "cmj", 0, false, true},
        {"CMJ2D-pad", "cmj2d", "cmj", 0, false, true},
        {"ZeroTwo-pad", "zerotwo", "cmj", 0, false, true},
        {"Halton", "halton", "cmj", 0, false, true},
        {"Sobol", "sobol", "cmj", 0, false, true},
        // What GPU renderers ship: Burley's padded 4D Owen-scrambled Sobol with hashed shuffling
        // (Cycles' Sobol-Burley), the production baseline of the equal-time answer.
        {"SobolBurley", "sobol-burley", "cmj", 0, false, true},
    };
}

oas::PatternRequest patternRequest(const SamplerSpec& s, std::uint32_t spp, std::uint32_t dims)
{
    oas::PatternRequest r;
    r.sampler = s.sampler;
    r.spp = spp;
    r.dims = dims;
    r.strength = s.strength;
    r.offset = s.offset;
    return r;
}

std::vector<std::uint32_t> countLadder(const SamplerSpec& s, std::uint32_t dims, std::uint32_t lo, std::uint32_t hi)
{
    std::vector<std::uint32_t> out;
    if (s.powersOfTwo) {
        for (std::uint64_t n = 1; n <= hi; n *= 2)
            if (n >= lo) out.push_back(std::uint32_t(n));
        return out;
    }
    const auto valid = oas::validCounts(s.sampler, s.strength, dims, std::max(1u, lo * 8 / 10), hi);
    for (int k = 0;; ++k) {
        const double target = lo * std::pow(2.0, k / 2.0);
        if (target > hi * 1.0001) break;
        std::uint32_t best = 0;
        double bestD = 0.25 + 1e-9;
        for (auto c : valid) {
            if (c < lo || c > hi) continue;
            const double d = std::abs(std::log2(c / target));
            if (d < bestD) bestD = d, best = c;
        }
        if (best && (out.empty() || out.back() != best)) out.push_back(best);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::uint32_t nearestCount(const SamplerSpec& s, std::uint32_t dims, std::uint32_t target)
{
    const double window = std::pow(2.0, 0.25);
    const auto lo = std::uint32_t(std::ceil(target / window)), hi = std::uint32_t(std::floor(target * window));
    std::vector<std::uint32_t> candidates;
    if (s.powersOfTwo) {
        for (std::uint64_t n = 1; n <= hi; n *= 2)
            if (n >= lo) candidates.push_back(std::uint32_t(n));
    } else {
        candidates = oas::validCounts(s.sampler, s.strength, dims, lo, hi);
    }
    std::uint32_t best = 0;
    double bestD = 1e300;
    for (auto c : candidates) {
        const double d = std::abs(std::log2(double(c) / target));
        if (d < bestD) bestD = d, best = c;
    }
    return best;
}

std::vector<Stats> statsOf(const std::vector<double>& est, std::size_t nf, std::uint32_t trials,
                           const std::vector<double>& references)
{
    std::vector<Stats> out(nf);
    for (size_t f = 0; f < nf; ++f) {
        double mean = 0, mse = 0, mse2 = 0;
        for (std::uint32_t t = 0; t < trials; ++t) {
            const double e = est[size_t(t) * nf + f];
            const double d2 = (e - references[f]) * (e - references[f]);
            mean += e;
            mse += d2;
            mse2 += d2 * d2;
        }
        mean /= trials;
        mse /= trials;
        double var = 0;
        for (std::uint32_t t = 0; t < trials; ++t) {
            const double d = est[size_t(t) * nf + f] - mean;
            var += d * d;
        }
        out[f].mean = mean;
        out[f].mse = mse;
        out[f].variance = trials > 1 ? var / (trials - 1) : 0;
        out[f].mseStderr = trials > 1 ? std::sqrt(std::max(0.0, mse2 / trials - mse * mse) / (trials - 1)) : 0;
    }
    return out;
}

std::vector<Stats> measure(const oas::Pattern& pattern, const std::vector<Integrand>& fs, const std::vector<double>& references,
                           std::uint32_t dims, std::uint32_t spp, std::uint32_t trials, std::uint32_t seed, unsigned threads)
{
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    const size_t nf = fs.size();
    std::vector<double> est(size_t(trials) * nf, 0.0);
    // Batches of pixels so that one batch holds at most ~16M floats.
    const std::uint64_t perPixel = std::uint64_t(spp) * dims;
    const std::uint32_t batch = std::uint32_t(std::clamp<std::uint64_t>((1u << 24) / perPixel, 1, trials));
    std::vector<float> buf(size_t(batch) * perPixel);
    for (std::uint32_t b0 = 0; b0 < trials; b0 += batch) {
        const std::uint32_t nb = std::min(batch, trials - b0);
        oas::SampleRequest req;
        req.x0 = b0;
        req.y0 = 0;
        req.width = nb;
        req.height = 1;
        req.spp = spp;
        req.dims = dims;
        req.seed = seed;
        oas::generateCpu(pattern, req, buf.data(), threads);
        // Evaluate: split pixels (or, for few pixels, samples) across threads.
        auto work = [&](std::uint32_t px, std::uint32_t s0, std::uint32_t s1, double* acc) {
            std::vector<double> v(nf);
            for (std::uint32_t s = s0; s < s1; ++s) {
                evaluateAll(fs, buf.data() + (size_t(px) * spp + s) * dims, dims, v.data());
                for (size_t f = 0; f < nf; ++f) acc[f] += v[f];
            }
        };
        const unsigned nt = threads;
        std::vector<std::vector<double>> partial(size_t(nb) * nt, std::vector<double>(nf, 0.0));
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < nt; ++t) {
            pool.emplace_back([&, t] {
                for (std::uint32_t px = 0; px < nb; ++px) {
                    const std::uint32_t s0 = std::uint32_t(std::uint64_t(spp) * t / nt);
                    const std::uint32_t s1 = std::uint32_t(std::uint64_t(spp) * (t + 1) / nt);
                    work(px, s0, s1, partial[size_t(px) * nt + t].data());
                }
            });
        }
        for (auto& th : pool) th.join();
        for (std::uint32_t px = 0; px < nb; ++px)
            for (size_t f = 0; f < nf; ++f) {
                double sum = 0;
                for (unsigned t = 0; t < nt; ++t) sum += partial[size_t(px) * nt + t][f];
                est[size_t(b0 + px) * nf + f] = sum / spp;
            }
    }
    return statsOf(est, nf, trials, references);
}

std::vector<Reference> rqmcReference(const std::vector<Integrand>& fs, std::uint32_t dims, std::uint32_t log2n,
                                     std::uint32_t reps, unsigned threads)
{
    oas::PatternRequest r;
    r.sampler = "sobol";
    r.spp = 1u << log2n;
    r.dims = dims;
    const oas::Pattern pat = oas::makePattern(r);
    const std::vector<double> zero(fs.size(), 0.0);
    const auto st = measure(pat, fs, zero, dims, r.spp, reps, 0x5EEDu + dims, threads);
    std::vector<Reference> out(fs.size());
    for (size_t f = 0; f < fs.size(); ++f) {
        out[f].value = st[f].mean;
        out[f].error = std::sqrt(st[f].variance / reps);
        out[f].method = "RQMC: " + std::to_string(reps) + " Owen-scrambled Sobol sets of 2^" + std::to_string(log2n) +
                        " points (error: standard error)";
        out[f].exact = false;
    }
    return out;
}

}  // namespace oas::study
