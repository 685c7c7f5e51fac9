#version 450
// The README's GLSL example as a whole shader: another project's compute shader that includes the
// oas library and writes dims values for every (pixel, sample). consumer.cpp checks them against
// the C++ twin (oas::sample) bit for bit.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#define OAS_NO_SOBOL  // this shader never receives a Sobol pattern
#include "oas/oas.glsl"

// One invocation per pixel, looping over all of the pixel's samples and dimensions. The library's
// loops all unroll, so they add nothing to lavapipe's silent cap of 65535 loop iterations per
// invocation: only this shader's own loops count.
layout(local_size_x = 8, local_size_y = 4) in;  // the host dispatches (width / 8, height / 4)

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
    uint seed = oas_pixel_seed(x, y, params.frameSeed);
    uint base = (y * params.width + x) * params.spp * params.dims;  // value (s, dim) at base + s * dims + dim

    // Baselines have no block state: one call per value. (oas_baseline_sample is oas_sample
    // without the OA code, which the calls below already bring in.)
    if (params.pattern.construction >= OAS_RANDOM) {
        for (uint s = 0u; s < params.spp; ++s)
            for (uint dim = 0u; dim < params.dims; ++dim)
                values[base + s * params.dims + dim] = oas_baseline_sample(params.pattern, seed, s, dim);
        return;
    }
    // OAs: dimension dim is column dim % blockDims of block dim / blockDims, and samples come in
    // passes of N. What a (pass, block, column) shares is made once, so each sample costs only
    // its own work.
    uint blockDims = params.pattern.blockDims;
    for (uint dim = 0u; dim < params.dims; ++dim) {
        uint block = dim / blockDims;
        for (uint first = 0u; first < params.spp; first += params.pattern.N) {
            OasBlock b = oas_block(params.pattern, seed, first, block);
            OasColumn c = oas_column(params.pattern, b.seed, dim - block * blockDims);
            for (uint s = first; s < min(params.spp, first + params.pattern.N); ++s)
                values[base + s * params.dims + dim] = oas_column_dim(params.pattern, c, oas_block_row(b, s));
        }
    }
}
