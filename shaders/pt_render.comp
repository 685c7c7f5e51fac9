#version 450
// The GPU path tracer: one invocation per pixel of a tile, a batch of samples per dispatch,
// radiance sums accumulated in a buffer (progressive rendering: the host adds batches until spp).
// The scene's dimension plan and effects arrive as specialization constants, so effects a scene
// does not call for compile away and consume no sample dimensions.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

layout(constant_id = 0) const uint oasSpecConstruction = 1u;
layout(constant_id = 1) const uint oasSpecOffset = 3u;
layout(constant_id = 2) const uint oasSpecFieldKind = 0u;
#define OAS_STATIC_CONSTRUCTION oasSpecConstruction
#define OAS_STATIC_OFFSET oasSpecOffset
#define OAS_STATIC_FIELD_KIND oasSpecFieldKind
// The Sobol baseline's direction numbers (oas::sobolDirections(), 1024 dims x 32 bits).
layout(std430, binding = 6) readonly buffer SobolDirections { uint sobolDirections[]; };
#define OAS_SOBOL_DIRECTION(dim, bit) sobolDirections[(dim) * 32u + (bit)]
#include "oas/oas.glsl"

const uint PT_ABSENT = 0xffffffffu;
layout(constant_id = 10) const bool PT_HAS_LENS = false;
layout(constant_id = 11) const bool PT_HAS_MOTION = false;
layout(constant_id = 12) const bool PT_NEE = true;
layout(constant_id = 13) const bool PT_MIS = true;
layout(constant_id = 14) const bool PT_HAS_DIELECTRIC = false;
layout(constant_id = 15) const uint PT_MAX_DEPTH = 1u;
layout(constant_id = 16) const uint PT_RR_START = 0u;
layout(constant_id = 20) const uint PT_DIM_PIXEL = 0u;
layout(constant_id = 21) const uint PT_DIM_LENS = PT_ABSENT;
layout(constant_id = 22) const uint PT_DIM_TIME = PT_ABSENT;
layout(constant_id = 23) const uint PT_DIM_VERTEX_BASE = 2u;
layout(constant_id = 24) const uint PT_DIM_VERTEX_STRIDE = 2u;
layout(constant_id = 25) const uint PT_OFF_LIGHT_SELECT = PT_ABSENT;
layout(constant_id = 26) const uint PT_OFF_LIGHT_UV = PT_ABSENT;
layout(constant_id = 27) const uint PT_OFF_BSDF_UV = PT_ABSENT;
layout(constant_id = 28) const uint PT_OFF_LOBE = PT_ABSENT;
layout(constant_id = 29) const uint PT_OFF_RR = PT_ABSENT;

#include "pt/pt_types.glsl"

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

layout(std430, binding = 0) readonly buffer Shapes { PtShape shapes[]; };
layout(std430, binding = 1) readonly buffer Materials { PtMaterial materials[]; };
layout(std430, binding = 2) readonly buffer Lights { PtLight lights[]; };
layout(std430, binding = 3) readonly buffer Nodes { PtNode nodes[]; };
layout(std430, binding = 4) readonly buffer Globals { PtGlobals globals; };
layout(std430, binding = 5) buffer Accumulation { vec4 accumulation[]; };
// The count of non-finite samples, 64 bits as two words: it cannot wrap in any render we can run.
layout(std430, binding = 7) buffer Counters { uint nonFiniteLow; uint nonFiniteHigh; } counters;

PtShape pt_shape(uint i) { return shapes[i]; }
PtMaterial pt_material(uint i) { return materials[i]; }
PtLight pt_light(uint i) { return lights[i]; }
PtNode pt_node(uint i) { return nodes[i]; }
PtGlobals pt_globals() { return globals; }
OasPattern pt_pattern() { return params.pattern; }

#include "pt/pt_trace.glsl"

void main()
{
    if (gl_GlobalInvocationID.x >= params.tileWidth || gl_GlobalInvocationID.y >= params.tileHeight) return;
    uint px = params.tileX + gl_GlobalInvocationID.x;
    uint py = params.tileY + gl_GlobalInvocationID.y;
    PtSampleState st;
    st.seed = oas_pixel_seed(px, py, params.seed);
    vec3 sum = vec3(0.0f);
    uint nonFinite = 0u;
    for (uint i = 0u; i < params.sampleCount; ++i) {
        st.index = params.firstSample + i;
        vec3 l = pt_radiance(st, px, py);
        if (pt_finite(l))
            sum += l;
        else
            ++nonFinite;
    }
    uint pixel = py * uint(globals.image.x) + px;
    accumulation[pixel] += vec4(sum, float(params.sampleCount));
    if (nonFinite > 0u) {
        // The add that wraps the low word carries into the high one; each wrap is seen by exactly
        // one add (the one whose old value was within nonFinite of 2^32), so the sum stays exact.
        uint before = atomicAdd(counters.nonFiniteLow, nonFinite);
        if (before + nonFinite < before) atomicAdd(counters.nonFiniteHigh, 1u);
    }
}
