#version 450
// The GPU path tracer: one invocation per pixel of a tile, a batch of samples per dispatch,
// exact radiance sums accumulated in a buffer (progressive rendering: the host adds batches until
// spp; any split of the samples gives the same sums, pt/pt_accumulate.glsl).
// The scene's dimension plan and effects arrive as specialization constants, so effects a scene
// does not call for compile away and consume no sample dimensions.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#ifdef PT_COUNT_OCCUPANCY
// The counting variant (oas-render-bench --kernels): how many of a subgroup's lanes are still on
// a path at each vertex, the ceiling of what a wavefront's compaction can give. The path
// tracer proper is built without it, so it needs no subgroup operations.
#extension GL_KHR_shader_subgroup_ballot : require
#endif

#include "pt/pt_kernel.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant) uniform RenderParams {
    OasPattern pattern;
    uint tileX;
    uint tileY;
    uint tileWidth;
    uint tileHeight;
    uint firstSample;
    uint sampleCount;
    uint seed;
} params;

OasPattern pt_pattern() { return params.pattern; }

/// pt_group_dims's values: from the prefetched samples (pt_kernel.glsl), or oas_draw. The same
/// bits either way (tests/render_test.cpp compares the sums word for word).
OasDraw pt_fetch_group(uint seed, uint index, uint first, uint count)
{
    if (PT_PREFETCH_DIMS == 0u) return oas_draw(params.pattern, seed, index, first, count);
    uint pixel = gl_GlobalInvocationID.y * params.tileWidth + gl_GlobalInvocationID.x;
    return pt_prefetched_group((pixel * params.sampleCount + (index - params.firstSample)) * (PT_PREFETCH_DIMS / 4u), first, count);
}
#define PT_FETCH_GROUP pt_fetch_group

#ifdef PT_COUNT_OCCUPANCY
layout(binding = PT_BINDING_OCCUPANCY, std430) buffer Occupancy { uint occupancy[]; };
/// Adds, for vertex v, the lanes of this subgroup that reach it and one subgroup step: lanes whose
/// path ended left the vertex loop and are inactive, so they are not in the ballot.
void pt_count_lanes(uint v)
{
    uvec4 live = subgroupBallot(true);
    if (subgroupElect()) {
        atomicAdd(occupancy[2u * v], subgroupBallotBitCount(live));
        atomicAdd(occupancy[2u * v + 1u], 1u);
    }
}
#define PT_ON_VERTEX pt_count_lanes
#endif

#include "pt/pt_trace.glsl"

/// PT_STAGE 2: the dimensions one path draws, without tracing it (a "radiance" that keeps the
/// fetches alive and is summable).
vec3 pt_stage_fetches_only(PtSampleState st)
{
    float total = 0.0f;
    for (uint v = 0u; v <= PT_MAX_DEPTH; ++v) {
        OasDraw d = pt_group_dims(st, v == 0u ? 0u : pt_vertex_dim(v, 0u), v == 0u ? pt_camera_dims_used() : pt_vertex_dims_used());
        [[unroll]] for (uint k = 0u; k < PT_GROUP_MAX; ++k) total += d.u[k];
    }
    return vec3(total);
}

void main()
{
    if (gl_GlobalInvocationID.x >= params.tileWidth || gl_GlobalInvocationID.y >= params.tileHeight) return;
    uint px = params.tileX + gl_GlobalInvocationID.x;
    uint py = params.tileY + gl_GlobalInvocationID.y;
    PtSampleState st;
    st.seed = oas_pixel_seed(px, py, params.seed);
    PtSum sum = pt_sum_zero();
    uint rejected = 0u;
    for (uint i = 0u; i < params.sampleCount; ++i) {
        st.index = params.firstSample + i;
        vec3 l = PT_STAGE == 0u ? pt_radiance(st, px, py) : (PT_STAGE == 2u ? pt_stage_fetches_only(st) : vec3(0.0f));
        if (pt_summable(l))
            sum = pt_sum_add(sum, pt_sum_of(l));
        else
            ++rejected;
    }
    pt_add_to_pixel(px, py, sum, params.sampleCount, rejected);
}
