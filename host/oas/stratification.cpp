#include "oas/stratification.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "oas/glsl_compat.hpp"

namespace oas {

std::uint32_t stratumOf(float x, std::uint32_t K)
{
    if (!(x >= 0.0f && x < 1.0f)) throw std::domain_error("sample value outside [0,1)");
    const double scaled = double(x) * 16777216.0;
    const auto F = std::uint64_t(scaled);
    if (double(F) != scaled) throw std::domain_error("sample value is not a multiple of 2^-24");
    return std::uint32_t((F * K) >> 24);
}

bool isStratified(const float* points, std::uint32_t n, std::uint32_t dims, const std::vector<std::uint32_t>& cols,
                  std::uint32_t K)
{
    std::uint64_t cells = 1;
    for (std::size_t i = 0; i < cols.size(); ++i) {
        cells *= K;
        if (cells > n) return false;  // more cells than points: cannot be equally filled
    }
    if (n % cells != 0) return false;
    std::vector<std::uint32_t> count(cells, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
        std::uint64_t cell = 0;
        for (auto c : cols) cell = cell * K + stratumOf(points[std::uint64_t(i) * dims + c], K);
        ++count[cell];
    }
    const std::uint64_t per = n / cells;
    for (auto c : count)
        if (c != per) return false;
    return true;
}

StratificationSummary summarize(const Pattern& p, const float* points, std::uint32_t n, std::uint32_t dims)
{
    StratificationSummary out;
    std::ostringstream line;
    auto emit = [&](bool ok) {
        out.lines.push_back((ok ? "  ok   " : "  FAIL ") + line.str());
        out.allKept = out.allKept && ok;
        line.str("");
    };
    bool valid = true;
    for (std::uint64_t i = 0; i < std::uint64_t(n) * dims; ++i) valid = valid && points[i] >= 0.0f && points[i] < 1.0f;
    line << "all " << std::uint64_t(n) * dims << " values in [0,1), none NaN";
    emit(valid);
    if (!valid) return out;
    const bool isOA = p.construction < glsl::OAS_RANDOM;
    if (n != p.N) {
        line << "summary needs exactly one pass of N = " << p.N << " points (have " << n << ")";
        emit(false);
        return out;
    }
    const bool lhsPromised = !isOA || p.offset == glsl::OAS_OFFSET_MJ || p.offset == glsl::OAS_OFFSET_CMJ;
    // Halton is N-stratified only where N is a power of a dimension's base; promise nothing there.
    // The Sobol samplers and (0,2) are N-stratified in 1D for powers of two only.
    const bool powerOfTwo = (p.N & (p.N - 1)) == 0;
    const bool base2Net = p.construction == glsl::OAS_SOBOL || p.construction == glsl::OAS_SOBOL_OWEN ||
                          p.construction == glsl::OAS_SOBOL_BURLEY || p.construction == glsl::OAS_ZERO_TWO;
    if (p.construction != glsl::OAS_RANDOM && p.construction != glsl::OAS_JITTERED_2D && p.construction != glsl::OAS_HALTON &&
        (powerOfTwo || !base2Net)) {
        std::uint32_t kept = 0, total = 0;
        const std::uint32_t K = lhsPromised ? p.N : p.s;
        for (std::uint32_t d = 0; d < dims; ++d, ++total) kept += isStratified(points, n, dims, {d}, K);
        line << "1D: " << kept << "/" << total << " dims stratified into " << K << " strata"
             << (K == p.N ? " (Latin hypercube)" : "");
        emit(kept == total);
    }
    if (isOA) {
        // Every t-subset of columns inside each block: exhaustive when few, else pairs only.
        const std::uint32_t t = p.strength;
        std::uint32_t kept = 0, total = 0;
        std::vector<std::uint32_t> cols(t);
        for (std::uint32_t block = 0; block * p.blockDims < dims; ++block) {
            const std::uint32_t lo = block * p.blockDims, hi = std::min(dims, lo + p.blockDims);
            if (hi - lo < t) continue;
            // Enumerate combinations of t columns in [lo, hi) in lexicographic order.
            for (std::uint32_t i = 0; i < t; ++i) cols[i] = lo + i;
            while (true) {
                kept += isStratified(points, n, dims, cols, p.s);
                ++total;
                int i = int(t) - 1;
                while (i >= 0 && cols[i] == hi - t + std::uint32_t(i)) --i;
                if (i < 0 || total >= 200000) break;
                ++cols[i];
                for (std::uint32_t j = std::uint32_t(i) + 1; j < t; ++j) cols[j] = cols[j - 1] + 1;
            }
        }
        line << t << "D: " << kept << "/" << total << " in-block " << t << "-subsets of dims stratified into " << p.s << "^" << t
             << " cells";
        emit(kept == total);
    } else if (p.construction == glsl::OAS_JITTERED_2D || p.construction == glsl::OAS_CMJ_2D) {
        std::uint32_t kept = 0, total = 0;
        for (std::uint32_t d = 0; d + 1 < dims; d += 2, ++total) {
            // A pair's nx * ny grid: check x strata nx and y strata ny jointly.
            std::vector<std::uint32_t> count(std::uint64_t(p.aux) * p.aux2, 0);
            for (std::uint32_t i = 0; i < n; ++i)
                ++count[std::uint64_t(stratumOf(points[std::uint64_t(i) * dims + d], p.aux)) * p.aux2 +
                        stratumOf(points[std::uint64_t(i) * dims + d + 1], p.aux2)];
            bool ok = true;
            for (auto c : count) ok = ok && c == 1;
            kept += ok;
        }
        line << "2D: " << kept << "/" << total << " dimension pairs stratified into " << p.aux << "x" << p.aux2 << " cells";
        emit(kept == total);
    }
    return out;
}

}  // namespace oas
