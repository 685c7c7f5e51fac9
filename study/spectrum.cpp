#include "spectrum.hpp"

#include "oas/oas_pattern.h"
#include "oas/periodogram.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <thread>

namespace oas::study {

Spectrum powerSpectrum(const oas::Pattern& pattern, std::uint32_t dimA, std::uint32_t dimB, std::uint32_t randomizations,
                       int radius, std::uint32_t userSeed, unsigned threads)
{
    if (radius < 0) throw std::invalid_argument("powerSpectrum: radius " + std::to_string(radius) + " < 0");
    if (randomizations == 0) throw std::invalid_argument("powerSpectrum: randomizations must be >= 1");
    if (pattern.N == 0) throw std::invalid_argument("powerSpectrum: pattern has N = 0");
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());

    const std::uint32_t N = pattern.N;
    const size_t W = size_t(2 * radius + 1);
    const size_t cells = W * W;

    // Randomizations are summed in fixed blocks (block size a function of the count only) and the
    // blocks added in order, so the floating-point sum, and hence the CSV, is the same for any
    // thread count. At most ~256 blocks bound the memory for large counts.
    const std::uint32_t blockSize = std::max<std::uint32_t>(8, (randomizations + 255) / 256);
    const std::uint32_t blocks = (randomizations + blockSize - 1) / blockSize;
    std::vector<double> blockSum(size_t(blocks) * cells, 0.0);
    std::atomic<std::uint32_t> next{0};

    auto worker = [&] {
        std::vector<float> xs(N), ys(N);
        std::vector<double> sums;
        for (std::uint32_t blk; (blk = next.fetch_add(1)) < blocks;) {
            double* acc = blockSum.data() + size_t(blk) * cells;
            const std::uint32_t i1 = std::min(randomizations, (blk + 1) * blockSize);
            for (std::uint32_t i = blk * blockSize; i < i1; ++i) {
                const std::uint32_t seed = oas::pixelSeed(i, 0, userSeed);
                for (std::uint32_t j = 0; j < N; ++j) {
                    xs[j] = oas::sample(pattern, seed, j, dimA);
                    ys[j] = oas::sample(pattern, seed, j, dimB);
                }
                sums.assign(cells, 0.0);
                oas::addPeriodogram(xs.data(), ys.data(), N, radius, sums);
                for (size_t c = 0; c < cells; ++c) acc[c] += sums[c];
            }
        }
    };
    const unsigned nt = std::min<unsigned>(threads, blocks);
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < nt; ++t) pool.emplace_back(worker);
    worker();
    for (auto& th : pool) th.join();

    Spectrum out;
    out.radius = radius;
    out.power.assign(cells, 0.0);
    for (std::uint32_t b = 0; b < blocks; ++b)
        for (size_t c = 0; c < cells; ++c) out.power[c] += blockSum[size_t(b) * cells + c];
    for (auto& p : out.power) p /= randomizations;
    // P(0) = N always: it says nothing about the pattern and would swamp the colour scale.
    out.power[size_t(radius) * W + size_t(radius)] = 0.0;
    return out;
}

double radialMean(const Spectrum& s, double kLow, double kHigh)
{
    double sum = 0;
    size_t n = 0;
    for (int ky = -s.radius; ky <= s.radius; ++ky)
        for (int kx = -s.radius; kx <= s.radius; ++kx) {
            if (kx == 0 && ky == 0) continue;
            const double k = std::hypot(double(kx), double(ky));
            if (k < kLow || k >= kHigh) continue;
            sum += s.at(kx, ky);
            ++n;
        }
    return n ? sum / double(n) : 0.0;
}

std::vector<double> radialProfile(const Spectrum& s)
{
    std::vector<double> out(size_t(s.radius) + 1, 0.0);
    for (int b = 1; b <= s.radius; ++b) out[size_t(b)] = radialMean(s, b - 0.5, b + 0.5);
    return out;
}

std::vector<std::pair<std::string, std::uint32_t>> projectionSamplers()
{
    // Counts near 128 that each construction makes exactly (Bose/Bush: q^2 = 121; CMJND t=4: 3^4).
    return {{"BoseCMJ", 121}, {"BoseMJ", 121},    {"BushMJ(t=2)", 121}, {"BoseBushCMJ", 128}, {"CMJND(t=4)", 81},
            {"Random", 128},  {"CMJ2D-pad", 128}, {"Halton", 128},      {"Sobol", 128}};
}

std::vector<ProjectionPair> projectionPairs(const SamplerSpec& spec, const oas::Pattern& pattern)
{
    // First dimension of the second block. Pairs within a block of a strength-t OA are
    // stratified (Jarosz et al. 2019, Sec. 4); the pair across blocks shows what padding leaves.
    std::uint32_t block = pattern.blockDims ? pattern.blockDims : 2;
    // The baselines' block sizes are the library's (oas_pattern.h; the GLSL's OAS_HALTON_BLOCK and
    // OAS_SOBOL_BLOCK equal them, tests/pattern_test.cpp checks).
    if (spec.sampler == "halton") block = OAS_HALTON_BLOCK_DIMS;
    if (spec.sampler == "sobol") block = OAS_SOBOL_BLOCK_DIMS;
    if (spec.sampler == "random") block = 1;
    const std::pair<std::uint32_t, std::uint32_t> candidates[] = {{0, 1}, {0, 2}, {1, 5}, {0, block}};
    std::vector<ProjectionPair> out;
    for (auto [a, b] : candidates) {
        if (std::any_of(out.begin(), out.end(), [&](const ProjectionPair& p) { return p.a == a && p.b == b; })) continue;
        // Built by appending: GCC 12 warns (-Wrestrict, a false positive) on "literal" + string.
        std::string name = (a == 0 && b == block) ? std::string("cross-block (") : std::string("(");
        name.append(std::to_string(a)).append(",").append(std::to_string(b)).append(")");
        out.push_back({a, b, name});
    }
    return out;
}

std::vector<std::string> spectrumColumns()
{
    return {"sampler", "pattern", "N", "pair", "kx", "ky", "power"};
}

void appendSpectrumRows(CsvTable& table, const std::string& sampler, const oas::Pattern& pattern, const ProjectionPair& pair,
                        const Spectrum& s)
{
    const std::string desc = oas::describe(pattern), n = std::to_string(pattern.N);
    for (int ky = -s.radius; ky <= s.radius; ++ky)
        for (int kx = -s.radius; kx <= s.radius; ++kx)
            table.add({sampler, desc, n, pair.name, std::to_string(kx), std::to_string(ky), fmtG(s.at(kx, ky), 6)});
}

void writeSpectra(const std::string& outDir, std::uint32_t randomizations, int radius, unsigned threads)
{
    CsvTable table(spectrumColumns());
    const auto all = studySamplers();
    for (auto& [label, N] : projectionSamplers()) {
        auto it = std::find_if(all.begin(), all.end(), [&](const SamplerSpec& s) { return s.label == label; });
        if (it == all.end()) continue;
        oas::Pattern pat;
        try {
            pat = oas::makePattern(patternRequest(*it, N, kProjectionDims));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "spectra: skip %s: %s\n", label.c_str(), e.what());
            continue;
        }
        for (const auto& pair : projectionPairs(*it, pat))
            appendSpectrumRows(table, label, pat, pair,
                               powerSpectrum(pat, pair.a, pair.b, randomizations, radius, kProjectionSeed, threads));
    }
    std::filesystem::create_directories(outDir);
    table.write(outDir + "/spectra.csv");
}

}  // namespace oas::study
