// The CPU reference tracer: shaders/pt/pt_trace.glsl compiled as C++ with GLM, reading the
// same flattened scene, dimension plan and OA patterns as the GPU kernel.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/baseline_columns.hpp"
#include "oas/oa_columns.hpp"
#include "render/tracer.hpp"

namespace oas::render {
namespace {

/// What the GPU kernel receives as specialization constants and bindings, per thread here.
struct CpuContext {
    const SceneData* data;
    const DimensionPlan* plan;
    pt::PtSpecialization spec;  ///< the kernel's specialization constants for the plan (every path kept)
    glsl::OasPattern pattern;
    std::optional<OaColumns> columns;  ///< the pattern's bulk evaluation, where it is an OA
    std::optional<BaselineColumns> baselineColumns;  ///< and where it is a baseline
    std::uint64_t generation;          ///< unique per context: keys the per-thread SampleRunMemo
};
thread_local const CpuContext* tContext = nullptr;
std::atomic<std::uint64_t> gContextGeneration{0};

CpuContext makeContext(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern)
{
    const bool oa = pattern.construction < glsl::OAS_RANDOM;
    return {&data,
            &plan,
            specialization(plan, pattern, KernelStage::PathTrace, nullptr),
            glsl::toGlsl(pattern),
            oa ? std::optional<OaColumns>(pattern) : std::nullopt,
            oa ? std::nullopt : std::optional<BaselineColumns>(pattern),
            ++gContextGeneration};
}

/// How many consecutive samples of a pixel the CPU tracer evaluates each OA dimension for at once.
constexpr std::uint32_t kSampleRun = 128;

/// The dimensions the run memo holds: the plan's and one group past them. The last vertex's group
/// can reach past the plan (every vertex group is fetched at the same width, and the last has no
/// roulette dimension), and those dimensions went through oas_draw one sample at a time, which
/// was 3% of interior_deep's CPU frame (perf).
std::uint32_t memoDims(const DimensionPlan& plan)
{
    return plan.sampleDims + kMaxGroupDims;
}

/// The sample values a thread is about to trace, made a dimension at a time for a run of up to
/// kSampleRun consecutive samples of one pixel and pass (OaColumns for the OAs: the library's
/// functions, vectorized across the run; BaselineColumns for the baselines, which need no rows).
/// The GPU kernel evaluates one sample per invocation and calls oas_draw; this loop takes a pixel's samples one after another, so a dimension's values
/// for the rest of the run cost a fraction of one value each. A dimension is made when a sample
/// first asks for it, from that sample to the end of the run: samples the tracer has passed never
/// ask again, and a deep dimension that only some paths reach is not made for the samples before
/// the first that reaches it. Every value is oas_sample's, bit for bit (tests/oa_columns_test.cpp).
struct SampleRunMemo {
    std::uint64_t generation = 0;
    std::uint32_t seed = 0;
    std::uint64_t first = 0, end = 0;       ///< the run's sample indices [first, end), in one pass
    std::vector<std::uint64_t> rowsFrom;    ///< per OA block: rows are made for [rowsFrom, end)
    std::vector<std::uint32_t> rows;        ///< [block][index - first]
    std::vector<std::uint64_t> valuesFrom;  ///< per dimension: values are made for [valuesFrom, end)
    std::vector<float> values;              ///< [dim][index - first]
};
thread_local SampleRunMemo tSampleRun;
/// One past the last sample index of the batch the thread is tracing (runs stop there).
thread_local std::uint64_t tBatchEnd = 0;

namespace shared {
/// pt_children_box (pt_box of two sibling nodes), each box four lanes at once (GCC vector
/// extensions: SSE on x86-64, NEON on AArch64, no intrinsics). Each lane does the scalar code's
/// IEEE operations on the same operands, and min and max are exact, so every result equals
/// pt_box's: the entry distance, or PT_INF (tests/render_test.cpp checks it against pt_box).
/// Only a zero's sign may differ, which no comparison of the walk sees. The scalar pt_box was a
/// third of interior_deep's CPU frame (perf); this made it 1.15x faster (render bench).
glm::vec2 pt_cpu_children_box(std::uint32_t first, glm::vec3 o, glm::vec3 invD, float tMax);
#define PT_CHILDREN_BOX pt_cpu_children_box
glsl::OasDraw pt_cpu_group_dims(std::uint32_t seed, std::uint32_t index, std::uint32_t first, std::uint32_t count);
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

using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));

/// pt_box of one node, four lanes at once: see pt_cpu_children_box.
inline float boxEntry(const PtNode& node, Float4 o, Float4 invD, float tMax)
{
    // Lane w holds the node's index bits: a denormal as a float, and a multiply by a denormal
    // costs a microcode assist (left in, it made CPU renders 1.4x slower), so it is cleared first.
    const Int4 xyz = {-1, -1, -1, 0};
    Int4 loBits, hiBits;
    std::memcpy(&loBits, &node.lo, sizeof loBits);
    std::memcpy(&hiBits, &node.hi, sizeof hiBits);
    const Float4 t0 = (Float4(loBits & xyz) - o) * invD, t1 = (Float4(hiBits & xyz) - o) * invD;
    // Lane w is (0 - 0) * 0 = 0 in both: it is pt_box's max(tn.z, 0) in tn as it stands, and
    // becomes its min(tf.z, tMax) in tf.
    const Float4 tn = t0 < t1 ? t0 : t1;
    const Float4 tf = (t0 < t1 ? t1 : t0) + Float4{0.0f, 0.0f, 0.0f, tMax};
    const Float4 tnSwap = __builtin_shuffle(tn, Int4{2, 3, 0, 1}), tfSwap = __builtin_shuffle(tf, Int4{2, 3, 0, 1});
    const Float4 tn2 = tn > tnSwap ? tn : tnSwap, tf2 = tf < tfSwap ? tf : tfSwap;
    const float enter = tn2[0] > tn2[1] ? tn2[0] : tn2[1];
    const float leave = tf2[0] < tf2[1] ? tf2[0] : tf2[1];
    return enter <= leave ? enter : PT_INF;
}

vec2 pt_cpu_children_box(uint first, vec3 o, vec3 invD, float tMax)
{
    const PtNode* nodes = tContext->data->nodes.data() + first;
    const Float4 o4 = {o.x, o.y, o.z, 0.0f}, invD4 = {invD.x, invD.y, invD.z, 0.0f};
    return vec2(boxEntry(nodes[0], o4, invD4, tMax), boxEntry(nodes[1], o4, invD4, tMax));
}

/// pt_cpu_group_dims within memoDims: the values from the thread's SampleRunMemo.
OasDraw pt_cpu_memo_group_dims(uint seed, uint sampleIndex, uint first, uint count)
{
    const CpuContext& c = *tContext;
    SampleRunMemo& m = tSampleRun;
    const std::uint64_t index = sampleIndex;
    if (m.generation != c.generation || m.seed != seed || index < m.first || index >= m.end) {
        const std::uint32_t dims = memoDims(*c.plan), blocks = dims / c.pattern.blockDims + 1;
        m.generation = c.generation;
        m.seed = seed;
        m.first = index;
        const std::uint32_t inPass =
            c.columns ? c.columns->samplesLeftInPass(sampleIndex) : c.baselineColumns->samplesLeftInPass(sampleIndex);
        m.end = index + std::min<std::uint64_t>({kSampleRun, inPass,
                                                 std::max<std::uint64_t>(tBatchEnd, index + 1) - index});
        m.rowsFrom.assign(blocks, m.end);
        m.rows.resize(std::size_t(blocks) * kSampleRun);
        m.valuesFrom.assign(dims, m.end);
        m.values.resize(std::size_t(dims) * kSampleRun);
    }
    const auto offset = std::uint32_t(index - m.first), runLeft = std::uint32_t(m.end - index);
    OasDraw d{};
    for (uint k = 0u; k < count; ++k) {
        const uint dim = first + k;
        float* values = &m.values[std::size_t(dim) * kSampleRun];
        if (m.valuesFrom[dim] > index && !c.columns) {
            const uint pairFirst = dim & ~1u;
            if (c.baselineColumns->padded2d() && pairFirst + 1 < memoDims(*c.plan)) {
                // Both dimensions of the pair: they share each sample's cell. The partner's
                // values from this index on are the same bits, so keep the earlier start.
                float* x = &m.values[std::size_t(pairFirst) * kSampleRun];
                c.baselineColumns->pairValues(seed, pairFirst, sampleIndex, runLeft, x + offset, x + kSampleRun + offset);
                m.valuesFrom[pairFirst] = std::min<std::uint64_t>(m.valuesFrom[pairFirst], index);
                m.valuesFrom[pairFirst + 1] = std::min<std::uint64_t>(m.valuesFrom[pairFirst + 1], index);
            } else {
                c.baselineColumns->values(seed, dim, sampleIndex, runLeft, values + offset);
                m.valuesFrom[dim] = index;
            }
        } else if (m.valuesFrom[dim] > index) {
            const uint block = dim / c.pattern.blockDims;
            std::uint32_t* rows = &m.rows[std::size_t(block) * kSampleRun];
            if (m.rowsFrom[block] > index) {
                c.columns->rows(seed, block, sampleIndex, runLeft, rows + offset);
                m.rowsFrom[block] = index;
            }
            c.columns->values(seed, dim, sampleIndex, runLeft, rows + offset, values + offset);
            m.valuesFrom[dim] = index;
        }
        d.u[k] = values[offset];
    }
    return d;
}

/// pt_group_dims for the CPU: through the memo, or oas_draw for dimensions past memoDims.
OasDraw pt_cpu_group_dims(uint seed, uint index, uint first, uint count)
{
    if (first + count > memoDims(*tContext->plan)) return oas_draw(tContext->pattern, seed, index, first, count);
    return pt_cpu_memo_group_dims(seed, index, first, count);
}

}  // namespace shared
static_assert(shared::PT_GROUP_MAX == kMaxGroupDims, "pt_sample_dims.glsl and plan.hpp disagree on the group size");

}  // namespace

namespace {
/// Makes `context` (or none) this thread's: the GLSL's accessors read it, its constants the plan's.
void bind(const CpuContext* context)
{
    tContext = context;
    tBatchEnd = 0;  // single samples (radianceCpu, nextEventCpu): runs of one
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

std::uint32_t fetchedDimsEnd(const DimensionPlan& plan, const Pattern& pattern)
{
    CpuContext context{};  // the plan's constants alone: no scene, no sampler state
    context.plan = &plan;
    context.spec = specialization(plan, pattern, KernelStage::PathTrace, nullptr);
    const CpuContext* const previous = tContext;
    bind(&context);
    std::uint32_t end = shared::pt_camera_dims_used();
    if (plan.maxDepth >= 1) end = std::max(end, shared::pt_vertex_dim(plan.maxDepth, 0u) + shared::pt_vertex_dims_used());
    bind(previous);
    return end;
}

glm::vec2 childrenBoxCpu(const SceneData& data, std::uint32_t first, glm::vec3 origin, glm::vec3 inverseDirection, float tMax)
{
    if (std::size_t(first) + 1 >= data.nodes.size()) throw std::out_of_range("childrenBoxCpu: no node pair there");
    CpuContext context{};  // the box test reads the scene's nodes alone
    context.data = &data;
    const CpuContext* const previous = tContext;
    tContext = &context;
    const glm::vec2 entries = shared::pt_cpu_children_box(first, origin, inverseDirection, tMax);
    tContext = previous;
    return entries;
}

glm::vec2 childrenBoxScalar(const SceneData& data, std::uint32_t first, glm::vec3 origin, glm::vec3 inverseDirection, float tMax)
{
    return {shared::pt_box(data.nodes.at(first), origin, inverseDirection, tMax),
            shared::pt_box(data.nodes.at(first + 1), origin, inverseDirection, tMax)};
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
        tBatchEnd = std::uint64_t(b.firstSample) + b.count;
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
