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
    pt::PtSpecialization spec;  ///< the kernel's specialization constants for the plan (every path kept)
    glsl::OasPattern pattern;
    std::uint64_t generation;  ///< unique per context: keys the per-thread pass-state memo
};
thread_local const CpuContext* tContext = nullptr;
std::atomic<std::uint64_t> gContextGeneration{0};

CpuContext makeContext(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern)
{
    return {&data, &plan, specialization(plan, pattern, KernelStage::PathTrace, nullptr), glsl::toGlsl(pattern),
            ++gContextGeneration};
}

/// A memo of the library's per-pass state for the pixel a thread is tracing, and nothing else:
/// the GPU kernel evaluates one sample per invocation and calls oas_draw, but this loop takes a
/// pixel's samples one after another, and making each OA block's OasBlock (its row permutation)
/// and each dimension's OasColumn (seeds, permutation keys, field constants) once per (pixel,
/// pass) instead of once per sample is worth 15-19% of the CPU tracer's OA paths/s on cornell7d and
/// blue_spheres9d, 5% on interior_deep (measured when oas_draw replaced this file's own fetch). Every value still comes from the library's functions
/// (oas_block, oas_column, oas_block_row, oas_column_dim: what oas_draw computes through oas_row
/// and oas_row_dim, bit for bit, as the library defines one through the other).
struct PassStateMemo {
    std::uint64_t generation = 0;
    std::uint32_t seed = 0, pass = 0;
    std::vector<glsl::OasBlock> blocks;  ///< per OA block
    std::vector<std::uint8_t> blockMade;
    std::vector<glsl::OasColumn> columns;  ///< per dimension
    std::vector<std::uint8_t> columnMade;

    void reset(const CpuContext& c, std::uint32_t pixelSeed, std::uint32_t passIndex)
    {
        generation = c.generation;
        seed = pixelSeed;
        pass = passIndex;
        const std::uint32_t dims = c.plan->sampleDims, blockCount = dims / c.pattern.blockDims + 1;
        blocks.resize(blockCount);
        columns.resize(dims);
        blockMade.assign(blockCount, 0);
        columnMade.assign(dims, 0);
    }
};
thread_local PassStateMemo tPassState;

namespace shared {
struct PtSampleState;
glsl::OasDraw pt_cpu_group_dims(PtSampleState st, std::uint32_t first, std::uint32_t count);
#define PT_FETCH_GROUP pt_cpu_group_dims
using namespace glm;
using namespace oas::pt;
using oas::glsl::oas_draw;
using oas::glsl::OAS_DRAW_MAX;
using oas::glsl::OasDraw;
using oas::glsl::OasPattern;
using uint = std::uint32_t;

// The plan entries of the table (pt/pt_constants.glsl), which the GPU kernel receives as
// specialization constants: this thread's variables, set from the bound context (bind()).
#define PT_DECLARE_THREAD_CONSTANT(NAME, ID, TYPE, DEFAULT, HOST) thread_local TYPE NAME = DEFAULT;
PT_PLAN_CONSTANTS(PT_DECLARE_THREAD_CONSTANT)
#undef PT_DECLARE_THREAD_CONSTANT

PtShape pt_shape(uint i)
{
    return tContext->data->shapes[i];
}
PtMaterial pt_material(uint i)
{
    return tContext->data->materials[i];
}
PtLight pt_light(uint i)
{
    return tContext->data->lights[i];
}
PtNode pt_node(uint i)
{
    return tContext->data->nodes[i];
}
PtGlobals pt_globals()
{
    return tContext->data->globals;
}
// No pt_pattern(): its one caller, the GLSL pt_group_dims, is replaced by PT_FETCH_GROUP here.

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "pt/pt_trace.glsl"
#pragma GCC diagnostic pop

/// The OA path of pt_cpu_group_dims: oas_draw's values, with the per-pass state from the memo.
/// Flattened (and so kept out of line): g++ otherwise calls the library's small functions (the
/// OA level, the permutation steps, the stratum point) out of line for every value.
[[gnu::flatten, gnu::noinline]] OasDraw pt_cpu_oa_group_dims(PtSampleState st, uint first, uint count)
{
    const OasPattern& pat = tContext->pattern;
    PassStateMemo& m = tPassState;
    const uint pass = glsl::oas_div_n(pat, st.index);
    if (m.generation != tContext->generation || m.seed != st.seed || m.pass != pass) m.reset(*tContext, st.seed, pass);
    OasDraw d{};
    glsl::OasRow row{};
    for (uint k = 0u, rowBlock = PT_ABSENT; k < count; ++k) {
        const uint dim = first + k, block = dim / pat.blockDims;
        if (!m.blockMade[block]) {
            m.blocks[block] = glsl::oas_block(pat, st.seed, st.index, block);
            m.blockMade[block] = 1;
        }
        if (block != rowBlock) {  // one row per block the group touches, as in oas_draw
            row = glsl::oas_block_row(m.blocks[block], st.index);
            rowBlock = block;
        }
        if (!m.columnMade[dim]) {
            m.columns[dim] = glsl::oas_column(pat, m.blocks[block].seed, dim - block * pat.blockDims);
            m.columnMade[dim] = 1;
        }
        d.u[k] = glsl::oas_column_dim(pat, m.columns[dim], row);
    }
    return d;
}

/// pt_group_dims for the CPU: the baselines (and dimensions past the plan) through oas_draw, the
/// OAs through the memo.
OasDraw pt_cpu_group_dims(PtSampleState st, uint first, uint count)
{
    const OasPattern& pat = tContext->pattern;
    if (pat.construction >= glsl::OAS_RANDOM || first + count > tContext->plan->sampleDims)
        return oas_draw(pat, st.seed, st.index, first, count);
    return pt_cpu_oa_group_dims(st, first, count);
}

}  // namespace shared
static_assert(shared::PT_GROUP_MAX == kMaxGroupDims, "pt_sample_dims.glsl and plan.hpp disagree on the group size");

}  // namespace

namespace {
/// Makes `context` (or none) this thread's: the GLSL's accessors read it, its constants the plan's.
void bind(const CpuContext* context)
{
    tContext = context;
    if (!context) return;
#define PT_BIND_THREAD_CONSTANT(NAME, ID, TYPE, DEFAULT, HOST) shared::NAME = context->spec.NAME;
    PT_PLAN_CONSTANTS(PT_BIND_THREAD_CONSTANT)
#undef PT_BIND_THREAD_CONSTANT
}

/// Binds a CpuContext to this thread for one scope.
class BoundContext {
public:
    BoundContext(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern)
        : context_(makeContext(data, plan, pattern))
    {
        bind(&context_);
    }
    ~BoundContext() { bind(nullptr); }
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
                       std::uint32_t sampleIndex, std::uint32_t vertex, std::uint32_t material, glm::vec3 x, glm::vec3 n,
                       glm::vec3 wo, float time)
{
    const BoundContext bound(data, plan, pattern);
    shared::PtSampleState st;
    st.seed = glsl::oas_pixel_seed(0, 0, seed);
    st.index = sampleIndex;
    const glsl::OasDraw d = shared::pt_group_dims(st, shared::pt_vertex_dim(vertex, 0u), shared::pt_vertex_dims_used());
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
        bind(&context);
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
        bind(nullptr);
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return rejectedTotal.load();
}

}  // namespace oas::render
