#version 450
// FaureGpu: the library's progressive sampler (oas_faure_value) on a list of (sample index,
// field element, key) triples, one invocation per value; the CPU twin computes the same list.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#define OAS_NO_SOBOL
// FAURE_POINTS_STATIC_DIGITS (a second build of this file): K fixed by specialization constant 0,
// as a renderer that specialises on its sequence would (OAS_STATIC_FAURE_DIGITS).
#ifdef FAURE_POINTS_STATIC_DIGITS
layout(constant_id = 0) const uint faureDigits = 1u;
#define OAS_STATIC_FAURE_DIGITS faureDigits
layout(constant_id = 1) const uint faureSmallStrata = 0u;
#define OAS_STATIC_SMALL_N faureSmallStrata
#endif
#include "oas/oas.glsl"

layout(local_size_x = 64) in;
layout(push_constant) uniform Params {
    OasFaure faure;
    uint count;
} params;
layout(std430, binding = 0) readonly buffer Triples { uint triples[]; };  // index, element, key
layout(std430, binding = 1) writeonly buffer Values { float values[]; };

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (k >= params.count) return;
    values[k] = oas_faure_value(params.faure, triples[3u * k + 1u], triples[3u * k], triples[3u * k + 2u]);
}
