#include "oas/generate_gpu.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "oas/glsl_compat.hpp"
#include "oas_generate_spv.h"
#include "oas_generate_hash_only_spv.h"
#include "oas_generate_unspecialised_spv.h"

namespace oas {
namespace {
constexpr std::uint32_t kLocalSize = 64;  // local_size_x of oas_generate.comp
constexpr std::uint32_t kGroupDims = 4;   // OAS_GROUP_DIMS of oas_generate.comp (OAs)
// Baselines: runs of samples x up to 8 of the dimensions made per invocation, so that with up
// to 8 dimensions neighbouring lanes take the same dimensions of neighbouring runs (the same
// Halton base and Sobol direction numbers in every lane). Past 8 the made dimensions are split
// into groups of equal size (12 made: 6 + 6), since lanes run in lock step and pay for the
// largest group: 8 + 4 cost as much as 8 + 8 (blue_spheres9d's 12 prefetched dimensions).
constexpr std::uint32_t kBaselineGroupDims = 8;
// The padded 2D baselines instead take the OAs' shape, runs of samples x one pair of dimensions:
// their per-(pass, dimension) state (OasPairColumn: permutation keys, the grid's reciprocals) is
// then made once per run and the pair's cell once per sample.
constexpr std::uint32_t kPairGroupDims = 2;

bool isPadded2d(const Pattern& p)
{
    return glsl::oas_is_padded_2d(glsl::toGlsl(p));
}
/// The baselines' dimensions to make: those below 32 not in r.unreadDims, and all from 32 on
/// (oas_generate.comp's nth_made_dim). The padded 2D baselines: the pairs with a made dimension.
std::uint32_t madeGroupsOrDims(const Pattern& p, const SampleRequest& r)
{
    std::uint32_t made = (r.dims >= 32 ? ~0u : (1u << r.dims) - 1u) & ~r.unreadDims;
    const std::uint32_t past32 = std::max(r.dims, 32u) - 32;
    if (!isPadded2d(p)) return std::uint32_t(__builtin_popcount(made)) + past32;
    made = (made | (made >> 1)) & 0x55555555u;
    return std::uint32_t(__builtin_popcount(made)) + (past32 + 1) / 2;
}

/// Made dimensions per baseline invocation: a pair, or the made dimensions in equal groups of
/// at most kBaselineGroupDims.
std::uint32_t baselineGroupDims(const Pattern& p, const SampleRequest& r)
{
    if (isPadded2d(p)) return kPairGroupDims;
    const std::uint32_t made = std::max(madeGroupsOrDims(p, r), 1u);
    const std::uint32_t groups = (made + kBaselineGroupDims - 1) / kBaselineGroupDims;
    return (made + groups - 1) / groups;
}

struct GenerateParams {  // the push-constant block of oas_generate.comp
    Pattern pattern;
    std::uint32_t x0, y0, width, spp, dims, seed, firstItem, itemCount, firstSample;
    std::uint32_t samplesPerRun, groupsPerBlock, groups, chunkFirstPoint, baselineGroupDims, unreadDims;
};
static_assert(sizeof(GenerateParams) == 124, "within the 128 bytes of push constants every device has");

/// How the kernel splits a request: each invocation evaluates `samplesPerRun` consecutive samples
/// of one pixel for `groupDims` dimensions (one OA block's), sharing the block and column state.
struct Layout {
    std::uint32_t samplesPerRun, groupsPerBlock, groups, runs;
};

/// Samples one invocation evaluates, for every construction. Lavapipe (Mesa 22.3) silently ends
/// an invocation's loops after 65535 iterations in all. The library's loops all unroll
/// (tests/loop_free_test.cpp), so only the kernel's own loops count: a run of 128 samples x 8
/// dimensions (a baseline's group; an OA group has 4) is far below the cap.
constexpr std::uint32_t kSamplesPerRun = 128;

Layout layoutFor(const Pattern& p, const SampleRequest& r)
{
    Layout l;
    l.samplesPerRun = std::min(kSamplesPerRun, std::max(r.spp, 1u));
    l.runs = (r.spp + l.samplesPerRun - 1) / l.samplesPerRun;
    if (p.construction >= glsl::OAS_RANDOM) {
        l.groupsPerBlock = 0;
        const std::uint32_t made = madeGroupsOrDims(p, r);
        l.groups = isPadded2d(p) ? made : (made + baselineGroupDims(p, r) - 1) / baselineGroupDims(p, r);
    } else {
        const std::uint32_t blocks = (r.dims + p.blockDims - 1) / p.blockDims;
        l.groupsPerBlock = (std::min(p.blockDims, r.dims) + kGroupDims - 1) / kGroupDims;
        l.groups = blocks * l.groupsPerBlock;
    }
    return l;
}
}  // namespace

GpuGenerator::GpuGenerator(vk::Context& context, Kernel kernel) : context_(context), kernel_(kernel) {}

vk::ComputePipeline& GpuGenerator::pipelineFor(const Pattern& pattern)
{
    const bool specialised = kernel_ == Kernel::Specialised;
    const auto key = specialised ? oas::specializationKey(pattern) : oas::SpecializationKey{};
    auto& slot = pipelines_[key];
    if (!slot) {
        struct Spirv {
            const std::uint32_t* code;
            std::size_t bytes;
        };
        const Spirv spirv = kernel_ == Kernel::HashOnly ? Spirv{oas_generate_hash_only_spv, sizeof(oas_generate_hash_only_spv)}
                            : kernel_ == Kernel::Unspecialised
                                ? Spirv{oas_generate_unspecialised_spv, sizeof(oas_generate_unspecialised_spv)}
                                : Spirv{oas_generate_spv, sizeof(oas_generate_spv)};
        vk::ComputePipeline::SpecConstants spec;
        if (specialised)
            spec = {{0, std::get<0>(key)},
                    {1, std::get<1>(key)},
                    {2, std::get<2>(key)},
                    {3, std::get<3>(key)},
                    {4, std::get<4>(key)},
                    {5, std::get<5>(key)}};
        const auto start = std::chrono::steady_clock::now();
        // Binding 0, the output, is a storage texel buffer of uint (oas_generate.comp says why).
        slot = std::make_unique<vk::ComputePipeline>(
            context_, spirv.code, spirv.bytes, 2, std::uint32_t(sizeof(GenerateParams)), spec,
            std::vector<vk::BindingKind>{vk::BindingKind::UintStorageTexelBuffer, vk::BindingKind::Uint4TexelBuffer});
        pipelineBuildSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return *slot;
}

GpuGenerator::~GpuGenerator() = default;

std::uint64_t GpuGenerator::pointsPerDispatch(std::uint32_t dims) const
{
    const auto& limits = context_.limits();
    // Cap a chunk at 64 MiB even where the device allows more: big enough to amortise a submit,
    // small enough that no single dispatch runs long (watchdogs on real GPUs).
    const std::uint64_t maxBytes = std::min<std::uint64_t>(
        {limits.maxStorageBufferRange, 64ull << 20, std::uint64_t(limits.maxTexelBufferElements) * sizeof(float)});
    std::uint64_t points = std::max<std::uint64_t>(1, maxBytes / (std::uint64_t(dims) * sizeof(float)));
    if (maxPointsPerDispatch_) points = std::min(points, maxPointsPerDispatch_);
    return points;
}

std::uint64_t GpuGenerator::runsPerDispatch(const Pattern& pattern, const SampleRequest& r) const
{
    const Layout layout = layoutFor(pattern, r);
    const auto& limits = context_.limits();
    const std::uint64_t byGroupCount = std::uint64_t(limits.maxComputeWorkGroupCount[0]) * kLocalSize *
                                       std::min<std::uint32_t>(limits.maxComputeWorkGroupCount[1], 64) / layout.groups;
    return std::max<std::uint64_t>(1, std::min(pointsPerDispatch(r.dims) / layout.samplesPerRun, byGroupCount));
}

bool GpuGenerator::fitsOneDispatch(const Pattern& pattern, const SampleRequest& r) const
{
    return std::uint64_t(r.width) * r.height * layoutFor(pattern, r).runs <= runsPerDispatch(pattern, r);
}

vk::Buffer& GpuGenerator::generateOnDevice(const Pattern& pattern, const SampleRequest& request)
{
    if (!fitsOneDispatch(pattern, request))
        throw InvalidArgument(std::to_string(request.width) + "x" + std::to_string(request.height) + " pixels x " +
                              std::to_string(request.spp) + " samples x " + std::to_string(request.dims) +
                              " dims take more than one dispatch (at most " + std::to_string(pointsPerDispatch(request.dims)) +
                              " points): split the request");
    dispatchAll(pattern, request, nullptr);
    return *buffer_;
}

void GpuGenerator::dispatchAll(const Pattern& pattern, const SampleRequest& r, float* out)
{
    const Layout layout = layoutFor(pattern, r);
    const std::uint64_t pixels = std::uint64_t(r.width) * r.height;
    const std::uint64_t totalPoints = pixels * r.spp;
    const std::uint64_t totalRuns = pixels * layout.runs;
    if (totalPoints > 0xffffffffull || totalRuns * layout.groups > 0xffffffffull)
        throw InvalidArgument("width * height * spp = " + std::to_string(totalPoints) + " (" +
                              std::to_string(totalRuns * layout.groups) + " work items) exceeds 2^32 - 1; split the request");
    // Chunks are whole runs, so a chunk's points are contiguous in the output.
    const auto& limits = context_.limits();
    const std::uint64_t runsPerChunk = runsPerDispatch(pattern, r);
    // Whole 16-byte texels, so that a kernel may read the buffer as a texel buffer of uvec4.
    const std::uint64_t chunkBytes =
        (std::max<std::uint64_t>(std::min(runsPerChunk * layout.samplesPerRun, totalPoints) * r.dims * sizeof(float), 4) + 15) /
        16 * 16;
    if (!buffer_ || buffer_->size() < chunkBytes) {
        buffer_.reset();
        buffer_ = std::make_unique<vk::Buffer>(context_, chunkBytes);
    }
    if (!sobol_) {
        const auto& directions = sobolDirections();
        sobol_ = std::make_unique<vk::Buffer>(context_, directions.size() * sizeof(std::uint32_t));
        std::memcpy(sobol_->data(), directions.data(), directions.size() * sizeof(std::uint32_t));
    }
    vk::Buffer* buffers[] = {buffer_.get(), sobol_.get()};
    vk::ComputePipeline& pipeline = pipelineFor(pattern);
    const std::uint32_t maxGroupsX = limits.maxComputeWorkGroupCount[0];
    // The output point where run `run` (counted over all pixels) starts.
    auto pointOfRun = [&](std::uint64_t run) {
        const std::uint64_t pixel = run / layout.runs;
        return pixel * r.spp + (run - pixel * layout.runs) * layout.samplesPerRun;
    };
    for (std::uint64_t first = 0; first < totalRuns; first += runsPerChunk) {
        const std::uint64_t runs = std::min(runsPerChunk, totalRuns - first);
        const std::uint64_t firstPoint = pointOfRun(first);
        const std::uint64_t endPoint = first + runs == totalRuns ? totalPoints : pointOfRun(first + runs);
        const auto items = std::uint32_t(runs * layout.groups);
        GenerateParams params{pattern,
                              r.x0,
                              r.y0,
                              r.width,
                              r.spp,
                              r.dims,
                              r.seed,
                              std::uint32_t(first * layout.groups),
                              items,
                              r.firstSample,
                              layout.samplesPerRun,
                              layout.groupsPerBlock,
                              layout.groups,
                              std::uint32_t(firstPoint),
                              baselineGroupDims(pattern, r),
                              pattern.construction >= glsl::OAS_RANDOM ? r.unreadDims : 0u};
        const std::uint32_t workGroups = (items + kLocalSize - 1) / kLocalSize;
        const std::uint32_t gx = std::min(workGroups, maxGroupsX);
        if (gx != 0)  // none where every dimension is unread
            context_.dispatch(pipeline, buffers, &params, sizeof(params), gx, (workGroups + gx - 1) / gx);
        if (out)
            std::memcpy(out + firstPoint * r.dims, buffer_->data(), std::size_t(endPoint - firstPoint) * r.dims * sizeof(float));
    }
}

void GpuGenerator::generate(const Pattern& pattern, const SampleRequest& request, float* out)
{
    dispatchAll(pattern, request, out);
}

}  // namespace oas
