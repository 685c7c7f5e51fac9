// The CPU reference tracer: shaders/pt/pt_trace.glsl compiled as C++ with GLM, reading the
// same flattened scene, dimension plan and OA patterns as the GPU kernel.
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "render/tracer.hpp"

namespace oas::render {
namespace {

/// What the GPU kernel receives as specialization constants and bindings, per thread here.
struct CpuContext {
    const SceneData* data;
    const DimensionPlan* plan;
    glsl::OasPattern pattern;
    std::uint64_t generation;  ///< unique per context: keys the per-thread sample-state cache
};
thread_local const CpuContext* tContext = nullptr;
std::atomic<std::uint64_t> gContextGeneration{0};

CpuContext makeContext(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern)
{
    return {&data, &plan, glsl::toGlsl(pattern), ++gContextGeneration};
}

/// The library's per-pass state for the pixel a thread is tracing: the GPU kernel evaluates one
/// sample per invocation, but this loop takes a pixel's samples one after another, so the block
/// and column state (seeds, permutation keys, field constants) is made once per (pixel, pass)
/// and each sample pays only for its rows and values: the same values as oas_row/oas_row_dim,
/// bit for bit (the library defines one through the other).
struct SampleStateCache {
    std::uint64_t generation = 0;
    std::uint32_t seed = 0, pass = 0;
    std::vector<glsl::OasBlock> blocks;
    std::vector<std::uint8_t> blockMade;
    std::vector<glsl::OasRow> rows;  ///< per block: the row of sample `rowIndex[block]`
    std::vector<std::uint32_t> rowIndex;
    std::vector<std::uint8_t> rowMade;
    std::vector<glsl::OasColumn> columns;  ///< per dimension
    std::vector<std::uint8_t> columnMade;

    void reset(const CpuContext& c, std::uint32_t pixelSeed, std::uint32_t passIndex)
    {
        generation = c.generation;
        seed = pixelSeed;
        pass = passIndex;
        const std::uint32_t dims = c.plan->sampleDims, blockCount = dims / c.pattern.blockDims + 1;
        blocks.resize(blockCount);
        rows.resize(blockCount);
        rowIndex.resize(blockCount);
        columns.resize(dims);
        blockMade.assign(blockCount, 0);
        rowMade.assign(blockCount, 0);
        columnMade.assign(dims, 0);
    }
};
thread_local SampleStateCache tSamples;

namespace shared {
struct PtSampleState;
struct PtDims;
PtDims pt_cpu_group_dims(PtSampleState st, uint first, uint count);
#define PT_FETCH_GROUP pt_cpu_group_dims
using namespace glm;
using namespace oas::pt;
using oas::glsl::OasPattern;
using oas::glsl::oas_sample;
using oas::glsl::oas_row;
using oas::glsl::oas_row_dim;
using oas::glsl::OasRow;
using oas::glsl::OAS_RANDOM;
using oas::glsl::oas_baseline_sample;
using uint = std::uint32_t;

const uint PT_ABSENT = kAbsent;
#define PT_HAS_LENS (tContext->plan->hasLens)
#define PT_HAS_MOTION (tContext->plan->hasMotion)
#define PT_NEE (tContext->plan->nee)
#define PT_MIS (tContext->plan->mis)
#define PT_HAS_DIELECTRIC (tContext->plan->lobe != kAbsent)
#define PT_MAX_DEPTH (tContext->plan->maxDepth)
#define PT_RR_START (tContext->plan->roulette != kAbsent ? tContext->plan->rouletteStart : 0u)
#define PT_DIM_PIXEL (tContext->plan->pixel)
#define PT_DIM_LENS (tContext->plan->lens)
#define PT_DIM_TIME (tContext->plan->time)
#define PT_DIM_VERTEX_BASE (tContext->plan->vertexBase)
#define PT_DIM_VERTEX_STRIDE (tContext->plan->vertexStride)
#define PT_OFF_LIGHT_SELECT (tContext->plan->lightSelect)
#define PT_OFF_LIGHT_UV (tContext->plan->lightUV)
#define PT_OFF_BSDF_UV (tContext->plan->bsdfUV)
#define PT_OFF_LOBE (tContext->plan->lobe)
#define PT_OFF_RR (tContext->plan->roulette)

PtShape pt_shape(uint i) { return tContext->data->shapes[i]; }
PtMaterial pt_material(uint i) { return tContext->data->materials[i]; }
PtLight pt_light(uint i) { return tContext->data->lights[i]; }
PtNode pt_node(uint i) { return tContext->data->nodes[i]; }
PtGlobals pt_globals() { return tContext->data->globals; }
// No pt_pattern(): its one caller, the GLSL pt_group_dims, is replaced by PT_FETCH_GROUP here.

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "pt/pt_trace.glsl"
#pragma GCC diagnostic pop

/// pt_group_dims for the CPU: the GLSL version's values through the cached per-pass state.
PtDims pt_cpu_group_dims(PtSampleState st, uint first, uint count)
{
    PtDims d;
    for (uint k = 0u; k < PT_GROUP_MAX; ++k) d.u[k] = 0.0f;
    const glsl::OasPattern& pat = tContext->pattern;
    if (pat.construction >= OAS_RANDOM || first + count > tContext->plan->sampleDims) {
        for (uint k = 0u; k < count; ++k) d.u[k] = oas_sample(pat, st.seed, st.index, first + k);
        return d;
    }
    SampleStateCache& c = tSamples;
    const uint pass = glsl::oas_div_n(pat, st.index);
    if (c.generation != tContext->generation || c.seed != st.seed || c.pass != pass) c.reset(*tContext, st.seed, pass);
    for (uint k = 0u; k < count; ++k) {
        const uint dim = first + k, block = dim / pat.blockDims;
        if (!c.blockMade[block]) {
            c.blocks[block] = glsl::oas_block(pat, st.seed, st.index, block);
            c.blockMade[block] = 1;
        }
        if (!c.rowMade[block] || c.rowIndex[block] != st.index) {
            c.rows[block] = glsl::oas_block_row(c.blocks[block], st.index);
            c.rowIndex[block] = st.index;
            c.rowMade[block] = 1;
        }
        if (!c.columnMade[dim]) {
            c.columns[dim] = glsl::oas_column(pat, c.blocks[block].seed, dim - block * pat.blockDims);
            c.columnMade[dim] = 1;
        }
        d.u[k] = glsl::oas_column_dim(pat, c.columns[dim], c.rows[block]);
    }
    return d;
}
}  // namespace shared
static_assert(shared::PT_GROUP_MAX == kMaxGroupDims, "pt_trace.glsl and plan.hpp disagree on the group size");

}  // namespace

namespace {
/// Binds a CpuContext to this thread for one scope (the GLSL's bindings read it).
class BoundContext {
public:
    BoundContext(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern)
        : context_(makeContext(data, plan, pattern))
    {
        tContext = &context_;
    }
    ~BoundContext() { tContext = nullptr; }
    BoundContext(const BoundContext&) = delete;
    BoundContext& operator=(const BoundContext&) = delete;

private:
    CpuContext context_;
};
}  // namespace

glm::vec3 radianceCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, std::uint32_t px,
                      std::uint32_t py, std::uint32_t seed, std::uint32_t sampleIndex)
{
    const BoundContext bound(data, plan, pattern);
    shared::PtSampleState st;
    st.seed = glsl::oas_pixel_seed(px, py, seed);
    st.index = sampleIndex;
    return shared::pt_radiance(st, px, py);
}

glm::vec3 nextEventCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, std::uint32_t seed,
                       std::uint32_t sampleIndex, std::uint32_t vertex, std::uint32_t material, glm::vec3 x,
                       glm::vec3 n, glm::vec3 wo, float time)
{
    const BoundContext bound(data, plan, pattern);
    shared::PtSampleState st;
    st.seed = glsl::oas_pixel_seed(0, 0, seed);
    st.index = sampleIndex;
    const shared::PtDims d = shared::pt_group_dims(st, shared::pt_vertex_dim(vertex, 0u), shared::pt_vertex_dims_used());
    return shared::pt_next_event(d, shared::pt_material(material), x, n, wo, time);
}

std::uint64_t traceCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, const SampleBatch& b,
                       Accumulation& accumulation, unsigned threads)
{
    const CpuContext context = makeContext(data, plan, pattern);
    const auto imageWidth = std::uint32_t(data.globals.image.x);
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<std::uint32_t> nextRow{0};
    std::atomic<std::uint64_t> rejectedTotal{0};
    auto work = [&] {
        tContext = &context;
        for (std::uint32_t row; (row = nextRow++) < b.height;) {
            const std::uint32_t py = b.y0 + row;
            for (std::uint32_t px = b.x0; px < b.x0 + b.width; ++px) {
                shared::PtSampleState st;
                st.seed = glsl::oas_pixel_seed(px, py, b.seed);
                pt::PtSum sum = pt::pt_sum_zero();
                std::uint32_t rejected = 0;
                for (std::uint32_t i = 0; i < b.count; ++i) {
                    st.index = b.firstSample + i;
                    const glm::vec3 l = shared::pt_radiance(st, px, py);
                    if (pt::pt_summable(l))
                        sum = pt::pt_sum_add(sum, pt::pt_sum_of(l));
                    else
                        ++rejected;
                }
                accumulation.addToPixel(std::size_t(py) * imageWidth + px, sum.lo, sum.mid, sum.hi, b.count, rejected);
                rejectedTotal += rejected;
            }
        }
        tContext = nullptr;
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return rejectedTotal.load();
}

}  // namespace oas::render
