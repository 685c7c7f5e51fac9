#version 450
// GoldenGpu: the GLSL library's one-shot oas_sample for a list of (sample index, dimension) pairs
// of one pixel, from pattern words uploaded as they are in tests/golden/patterns.json. One
// invocation per value and no specialisation: a single pipeline serves every construction (the
// specialised kernel's agreement with the CPU twin is GpuCpu's job).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(std430, binding = 2) readonly buffer SobolDirections { uint sobolDirections[]; };
#define OAS_SOBOL_DIRECTION(dim, bit) sobolDirections[(dim) * 32u + (bit)]
#include "oas/oas.glsl"

layout(local_size_x = 8) in;
layout(push_constant) uniform Params {
    OasPattern pattern;
    uint pixelSeed;
    uint count;
} params;
layout(std430, binding = 0) readonly buffer Points { uvec2 points[]; };  // (index, dim)
layout(std430, binding = 1) writeonly buffer Values { float values[]; };

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (k >= params.count) return;
    values[k] = oas_sample(params.pattern, params.pixelSeed, points[k].x, points[k].y);
}
