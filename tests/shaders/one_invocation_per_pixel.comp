#version 450
// The embedding case that lavapipe's silent 65535-iteration loop cap used to break: one
// invocation per pixel loops over every sample and dimension. Mode 0 calls oas_sample for each
// value (the one-shot API); mode 1 makes the block and column state once per pass (OasBlock,
// OasColumn) and reuses it (the fast-path API). Both must equal the CPU twin bit for bit.
// Specialised on (construction, offset, field kind) as the header recommends: unspecialised,
// lavapipe also runs (and counts) the loops of every construction the pattern does not use.
#extension GL_GOOGLE_include_directive : require
layout(constant_id = 0) const uint specConstruction = 1u;
layout(constant_id = 1) const uint specOffset = 3u;
layout(constant_id = 2) const uint specFieldKind = 0u;
#define OAS_STATIC_CONSTRUCTION specConstruction
#define OAS_STATIC_OFFSET specOffset
#define OAS_STATIC_FIELD_KIND specFieldKind
#define OAS_NO_SOBOL  // this shader never gets a Sobol pattern
#include "oas/oas.glsl"

layout(local_size_x = 8) in;
layout(push_constant) uniform Params {
    OasPattern pattern;
    uint pixels;
    uint spp;
    uint dims;
    uint mode;
} params;
layout(std430, binding = 0) writeonly buffer Samples { float values[]; };

void main()
{
    uint pixel = gl_GlobalInvocationID.x;
    if (pixel >= params.pixels) return;
    uint seed = oas_pixel_seed(pixel, 7u, 0x5eedu);
    uint base = pixel * params.spp * params.dims;
    if (params.mode == 0u || OAS_CONSTRUCTION(params.pattern) >= OAS_RANDOM) {
        for (uint i = 0u; i < params.spp; ++i)
            for (uint d = 0u; d < params.dims; ++d)
                values[base + i * params.dims + d] = oas_sample(params.pattern, seed, i, d);
        return;
    }
    for (uint d = 0u; d < params.dims; ++d) {
        uint block = d / params.pattern.blockDims;
        uint col = d - block * params.pattern.blockDims;
        for (uint i = 0u; i < params.spp;) {
            OasBlock b = oas_block(params.pattern, seed, i, block);
            OasColumn c = oas_column(params.pattern, b.seed, col);
            uint end = min(params.spp, b.firstIndex + params.pattern.N);
            for (; i < end; ++i) values[base + i * params.dims + d] = oas_column_dim(params.pattern, c, oas_block_row(b, i));
        }
    }
}
