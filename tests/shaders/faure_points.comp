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
    uint perInvocation;  ///< values each invocation makes, in a loop of its own
    uint burn;           ///< loop iterations spent before them (lavapipe's cap, see below)
} params;
layout(std430, binding = 0) readonly buffer Triples { uint triples[]; };  // index, element, key
layout(std430, binding = 1) writeonly buffer Values { float values[]; };  // count, then one per invocation

// Lavapipe ends an invocation's loops after 65535 iterations in all, silently. With many values per
// invocation and a burn that leaves only a few spare iterations, a loop the library left in (one
// the compiler did not unroll) ends the value loop early: those values stay NaN and differ from the
// twin's (FaureGpu.ManyValuesInOneInvocationAddNoLoopIterations).
void main()
{
    uint first = gl_GlobalInvocationID.x * params.perInvocation;
    if (first >= params.count) return;
    uint burnt = 0u;
    for (uint b = 0u; b < params.burn; ++b) burnt += b ^ first;
    values[params.count + gl_GlobalInvocationID.x] = float(burnt & 1u);  // keeps the burn loop
    uint end = min(params.count, first + params.perInvocation);
    for (uint k = first; k < end; ++k)
        values[k] = oas_faure_value(params.faure, triples[3u * k + 1u], triples[3u * k], triples[3u * k + 2u]);
}
