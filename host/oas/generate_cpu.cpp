// CPU reference generation: the shared GLSL code (glsl_compat.hpp), laid out like the GPU kernel.
#include <algorithm>
#include <optional>
#include <thread>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/baseline_columns.hpp"
#include "oas/oa_columns.hpp"
#include "oas/pattern.hpp"

namespace oas {
using glsl::toGlsl;

std::uint32_t pixelSeed(std::uint32_t x, std::uint32_t y, std::uint32_t seed)
{
    return glsl::oas_pixel_seed(x, y, seed);
}

float sample(const Pattern& pattern, std::uint32_t seed, std::uint32_t index, std::uint32_t dim)
{
    return glsl::oas_sample(toGlsl(pattern), seed, index, dim);
}

namespace {
// The baselines: BaselineColumns, runs of up to kRunSamples samples of one pass; a padded 2D
// pattern's pairs two dimensions a call (their cell once per sample), the others one.
void generateBaseline(const BaselineColumns& columns, std::uint32_t seed, const SampleRequest& r, float* pixelOut,
                      std::vector<float>& values)
{
    constexpr std::uint32_t kRunSamples = 1024;
    values.resize(2 * kRunSamples);
    auto scatter = [&](std::uint32_t done, std::uint32_t dim, std::uint32_t count, const float* from) {
        float* dst = pixelOut + std::size_t(done) * r.dims + dim;
        for (std::uint32_t k = 0; k < count; ++k) dst[std::size_t(k) * r.dims] = from[k];
    };
    for (std::uint32_t done = 0; done < r.spp;) {
        const std::uint32_t first = r.firstSample + done;
        const std::uint32_t count = std::min({r.spp - done, columns.samplesLeftInPass(first), kRunSamples});
        for (std::uint32_t dim = 0; dim < r.dims; ++dim) {
            if (columns.padded2d() && dim % 2 == 0 && dim + 1 < r.dims) {
                columns.pairValues(seed, dim, first, count, values.data(), values.data() + kRunSamples);
                scatter(done, dim, count, values.data());
                scatter(done, ++dim, count, values.data() + kRunSamples);
                continue;
            }
            columns.values(seed, dim, first, count, values.data());
            scatter(done, dim, count, values.data());
        }
        done += count;
    }
}

// The OAs: OaColumns (oa_columns.hpp), the library's fast path (block and column state once per
// run, one row per sample and block) run over up to kRunSamples samples of one pass at a time, one
// dimension per call, vectorized across the samples.
void generateOa(const OaColumns& columns, std::uint32_t seed, const SampleRequest& r, float* pixelOut,
                std::vector<std::uint32_t>& rows, std::vector<float>& values)
{
    constexpr std::uint32_t kRunSamples = 1024;
    rows.resize(kRunSamples);
    values.resize(kRunSamples);
    const std::uint32_t blockDims = columns.pattern().blockDims;
    for (std::uint32_t done = 0; done < r.spp;) {
        const std::uint32_t first = r.firstSample + done;
        const std::uint32_t count = std::min({r.spp - done, columns.samplesLeftInPass(first), kRunSamples});
        for (std::uint32_t block = 0, d0 = 0; d0 < r.dims; ++block, d0 += blockDims) {
            columns.rows(seed, block, first, count, rows.data());
            for (std::uint32_t dim = d0; dim < std::min(d0 + blockDims, r.dims); ++dim) {
                columns.values(seed, dim, first, count, rows.data(), values.data());
                float* dst = pixelOut + std::size_t(done) * r.dims + dim;
                for (std::uint32_t k = 0; k < count; ++k) dst[std::size_t(k) * r.dims] = values[k];
            }
        }
        done += count;
    }
}
}  // namespace

void generateCpu(const Pattern& pattern, const SampleRequest& r, float* out, unsigned threads)
{
    const glsl::OasPattern pat = toGlsl(pattern);
    const std::uint64_t pixels = std::uint64_t(r.width) * r.height;
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    const bool oa = pat.construction < glsl::OAS_RANDOM;
    const std::optional<OaColumns> columns = oa ? std::optional<OaColumns>(pattern) : std::nullopt;
    const std::optional<BaselineColumns> baselineColumns = oa ? std::nullopt : std::optional<BaselineColumns>(pattern);
    auto work = [&](std::uint64_t begin, std::uint64_t end) {
        std::vector<std::uint32_t> rows;
        std::vector<float> values;
        for (std::uint64_t px = begin; px < end; ++px) {
            const std::uint32_t x = r.x0 + std::uint32_t(px % r.width);
            const std::uint32_t y = r.y0 + std::uint32_t(px / r.width);
            const std::uint32_t seed = glsl::oas_pixel_seed(x, y, r.seed);
            float* pixelOut = out + px * r.spp * r.dims;
            if (!oa) {  // baselines: runs of one pass
                generateBaseline(*baselineColumns, seed, r, pixelOut, values);
                continue;
            }
            generateOa(*columns, seed, r, pixelOut, rows, values);
        }
    };
    if (threads == 1 || pixels < 2) {
        work(0, pixels);
        return;
    }
    std::vector<std::thread> pool;
    const std::uint64_t per = (pixels + threads - 1) / threads;
    for (unsigned t = 0; t < threads; ++t) {
        const std::uint64_t b = t * per, e = std::min(pixels, b + per);
        if (b < e) pool.emplace_back(work, b, e);
    }
    for (auto& th : pool) th.join();
}

}  // namespace oas
