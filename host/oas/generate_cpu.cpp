// CPU reference generation: the shared GLSL code (glsl_compat.hpp), laid out like the GPU kernel.
#include <algorithm>
#include <thread>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"

namespace oas {
using glsl::toGlsl;

float sample(const Pattern& pattern, std::uint32_t seed, std::uint32_t index, std::uint32_t dim)
{
    return glsl::oas_sample(toGlsl(pattern), seed, index, dim);
}

void generateCpu(const Pattern& pattern, const SampleRequest& r, float* out, unsigned threads)
{
    const glsl::OasPattern pat = toGlsl(pattern);
    const std::uint64_t pixels = std::uint64_t(r.width) * r.height;
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    auto work = [&](std::uint64_t begin, std::uint64_t end) {
        for (std::uint64_t px = begin; px < end; ++px) {
            const std::uint32_t x = r.x0 + std::uint32_t(px % r.width);
            const std::uint32_t y = r.y0 + std::uint32_t(px / r.width);
            const std::uint32_t seed = glsl::oas_pixel_seed(x, y, r.seed);
            float* dst = out + px * r.spp * r.dims;
            for (std::uint32_t i = r.firstSample; i != r.firstSample + r.spp; ++i) {
                if (pat.construction >= glsl::OAS_RANDOM) {
                    for (std::uint32_t d = 0; d < r.dims; ++d) *dst++ = glsl::oas_sample(pat, seed, i, d);
                    continue;
                }
                // The fast path the GPU kernel takes too: one row computation per OA block.
                for (std::uint32_t block = 0, d = 0; d < r.dims; ++block) {
                    const glsl::OasRow row = glsl::oas_row(pat, seed, i, block);
                    for (std::uint32_t col = 0; col < pat.blockDims && d < r.dims; ++col, ++d)
                        *dst++ = glsl::oas_row_dim(pat, row, col);
                }
            }
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
