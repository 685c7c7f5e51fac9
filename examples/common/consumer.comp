#version 450
// The README's GLSL example as a whole shader: another project's compute shader that includes the
// oas library and writes dims values for every (pixel, sample). consumer.cpp checks them against
// the C++ twin (oas::sample) bit for bit.
#extension GL_GOOGLE_include_directive : require
#define OAS_NO_SOBOL  // this shader never receives a Sobol pattern
#include "oas/oas.glsl"

// One invocation per (pixel, sample), never a loop over samples: lavapipe silently ends an
// invocation's loops after 65535 iterations in all.
layout(local_size_x = 8, local_size_y = 4) in;  // the host dispatches (width / 8, height / 4, spp)

layout(push_constant) uniform Params {
    OasPattern pattern;  // made by oas::makePattern (or oas_make_pattern in C), uploaded as is
    uint frameSeed;
    uint spp;
    uint dims;
    uint width;
} params;

layout(std430, binding = 0) writeonly buffer Samples { float values[]; };  // [pixel][sample][dim]

void main()
{
    uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
    uint sampleIndex = gl_GlobalInvocationID.z;
    uint seed = oas_pixel_seed(x, y, params.frameSeed);
    uint base = ((y * params.width + x) * params.spp + sampleIndex) * params.dims;

    // Baselines have no row state. oas_baseline_sample is oas_sample without the OA code, which
    // the row API below already brings in (inlined twice, it made this program take 3.4 s instead
    // of 2.0 s on lavapipe).
    if (params.pattern.construction >= OAS_RANDOM) {
        for (uint dim = 0u; dim < params.dims; ++dim)
            values[base + dim] = oas_baseline_sample(params.pattern, seed, sampleIndex, dim);
        return;
    }
    // Dimension dim is column dim - block * blockDims of OA block dim / blockDims: make the row
    // once per block and reuse it for the block's columns.
    uint blockDims = params.pattern.blockDims;
    for (uint block = 0u; block * blockDims < params.dims; ++block) {
        OasRow row = oas_row(params.pattern, seed, sampleIndex, block);
        uint first = block * blockDims;
        for (uint dim = first; dim < min(params.dims, first + blockDims); ++dim)
            values[base + dim] = oas_row_dim(params.pattern, row, dim - first);
    }
}
