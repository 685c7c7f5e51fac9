// pt_sample_dims.glsl - the sample dimensions a path draws: the sample being traced
// (PtSampleState), how many dimensions the camera and each vertex group use, and the one fetch of
// a group (pt_group_dims, an oas_draw).
// Part of the path tracer; include pt/pt_trace.glsl rather than this file. Depends on the oas
// library (oas_draw, OAS_DRAW_MAX; or the includer's PT_FETCH_GROUP), the accessor pt_pattern and
// the plan constants (pt_constants.glsl).
// Shared verbatim with the C++ reference tracer: keep to the subset pt_trace.glsl describes (float
// literals with an f suffix, no swizzles, no in/out params).
#ifndef PT_SAMPLE_DIMS_GLSL
#define PT_SAMPLE_DIMS_GLSL

/// The sample being traced: the pixel's OA seed and the sample index.
struct PtSampleState {
    uint seed;
    uint index;
};

/// Most dimensions of one group: the camera's (pixel, lens, time: 6 with the alignment gap) or one
/// path vertex's (light.uv, bsdf.uv, light.select, lobe, roulette: 8 with the gap). The library's
/// oas_draw fetches a group; host/render/plan.hpp's kMaxGroupDims is checked against this.
const uint PT_GROUP_MAX = OAS_DRAW_MAX;

/// Dimensions the camera group uses: pixel, then lens and time where present (not the alignment
/// gap before the first vertex group).
uint pt_camera_dims_used()
{
    return PT_HAS_MOTION ? PT_DIM_TIME + 1u : (PT_HAS_LENS ? PT_DIM_LENS + 2u : PT_DIM_PIXEL + 2u);
}

/// Dimensions a vertex group uses: up to its last present effect (not the alignment gap).
uint pt_vertex_dims_used()
{
    uint n = 0u;
    if (PT_OFF_LIGHT_UV != PT_ABSENT) n = max(n, PT_OFF_LIGHT_UV + 2u);
    if (PT_OFF_BSDF_UV != PT_ABSENT) n = max(n, PT_OFF_BSDF_UV + 2u);
    if (PT_OFF_LIGHT_SELECT != PT_ABSENT) n = max(n, PT_OFF_LIGHT_SELECT + 1u);
    if (PT_OFF_LOBE != PT_ABSENT) n = max(n, PT_OFF_LOBE + 1u);
    if (PT_OFF_RR != PT_ABSENT) n = max(n, PT_OFF_RR + 1u);
    return n;
}

/// Fetches a whole group at once, straight from the OA library (no sample buffers): oas_draw, the
/// library's one sample-fetch call. pt_radiance calls this at one site only: the GPU compiler
/// inlines the sampler wherever it is called, and with a call per use (a dozen in the tracer) the
/// lavapipe pipeline build takes ~20 s, against ~0.1 s with the sampler replaced by one hash.
#ifdef PT_FETCH_GROUP
// The includer may supply its own fetch with the same values, PT_FETCH_GROUP(seed, index, first,
// count): the C++ twin's run memo (host/render/tracer_cpu.cpp), the GPU kernel's prefetched
// samples (pt_render.comp).
OasDraw pt_group_dims(PtSampleState st, uint first, uint count) { return PT_FETCH_GROUP(st.seed, st.index, first, count); }
#else
OasDraw pt_group_dims(PtSampleState st, uint first, uint count)
{
    return oas_draw(pt_pattern(), st.seed, st.index, first, count);
}
#endif

/// First dimension of vertex v's group (v = 1 is the first surface hit).
uint pt_vertex_dim(uint v, uint offset) { return PT_DIM_VERTEX_BASE + (v - 1u) * PT_DIM_VERTEX_STRIDE + offset; }

#endif // PT_SAMPLE_DIMS_GLSL
