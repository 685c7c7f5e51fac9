// The CPU reference tracer: shaders/pt/pt_trace.glsl compiled as C++ with GLM, reading the
// same flattened scene, dimension plan and OA patterns as the GPU kernel.
#include <algorithm>
#include <atomic>
#include <thread>

#include "oas/glsl_compat.hpp"
#include "render/tracer.hpp"

namespace oas::render {
namespace {

/// What the GPU kernel receives as specialization constants and bindings, per thread here.
struct CpuContext {
    const SceneData* data;
    const DimensionPlan* plan;
    glsl::OasPattern pattern;
};
thread_local const CpuContext* tContext = nullptr;

namespace shared {
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
OasPattern pt_pattern() { return tContext->pattern; }

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "pt/pt_trace.glsl"
#pragma GCC diagnostic pop
}  // namespace shared
static_assert(shared::PT_GROUP_MAX == kMaxGroupDims, "pt_trace.glsl and plan.hpp disagree on the group size");

}  // namespace

namespace {
/// Binds a CpuContext to this thread for one scope (the GLSL's bindings read it).
class BoundContext {
public:
    BoundContext(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern)
        : context_{&data, &plan, glsl::toGlsl(pattern)}
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
                       std::vector<float>& accumulation, unsigned threads)
{
    const CpuContext context{&data, &plan, glsl::toGlsl(pattern)};
    const auto imageWidth = std::uint32_t(data.globals.image.x);
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<std::uint32_t> nextRow{0};
    std::atomic<std::uint64_t> nonFinite{0};
    auto work = [&] {
        tContext = &context;
        for (std::uint32_t row; (row = nextRow++) < b.height;) {
            const std::uint32_t py = b.y0 + row;
            for (std::uint32_t px = b.x0; px < b.x0 + b.width; ++px) {
                shared::PtSampleState st;
                st.seed = glsl::oas_pixel_seed(px, py, b.seed);
                glm::vec3 sum(0.0f);
                for (std::uint32_t i = 0; i < b.count; ++i) {
                    st.index = b.firstSample + i;
                    const glm::vec3 l = shared::pt_radiance(st, px, py);
                    if (shared::pt_finite(l))
                        sum += l;
                    else
                        ++nonFinite;
                }
                float* acc = &accumulation[(std::size_t(py) * imageWidth + px) * 4];
                acc[0] += sum.x;
                acc[1] += sum.y;
                acc[2] += sum.z;
                acc[3] += float(b.count);
            }
        }
        tContext = nullptr;
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return nonFinite.load();
}

}  // namespace oas::render
