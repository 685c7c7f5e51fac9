#version 450
// Another renderer's way of using the library, and the one lavapipe's silent cap of 65535 loop
// iterations per invocation would cut short if the library looped per value: one
// invocation per pixel loops over `spp` samples and `dims` dimensions (from dimBase) of its pixel.
// Mode 0 calls oas_sample for each value (the one-shot API); mode 1 makes the block and column
// state once per pass (OasBlock, OasColumn) and reuses it (the fast-path API). Both must equal the
// CPU twin bit for bit (tests/loop_free_test.cpp).
//
// Built twice: with -DSPECIALIZED the pattern kind comes from specialization constants
// (OAS_STATIC_*), without it the shader handles every construction, field and offset at run time.
//
// Lavapipe ends an invocation's loops after 65535 iterations in all, silently. Before the sampling
// loops, this shader spends `burn` iterations of its own. The test first finds, with CALIBRATE set
// (the same loops, no library code), the largest burn that still leaves the loops enough
// iterations; it then runs the library with a burn only a few iterations below that, so that any
// loop iteration the library added would end the sampling loops early and show as wrong values.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#ifdef SPECIALIZED
layout(constant_id = 0) const uint specConstruction = 1u;
layout(constant_id = 1) const uint specOffset = 3u;
layout(constant_id = 2) const uint specFieldKind = 0u;
#define OAS_STATIC_CONSTRUCTION specConstruction
#define OAS_STATIC_OFFSET specOffset
#define OAS_STATIC_FIELD_KIND specFieldKind
#endif
layout(constant_id = 3) const bool CALIBRATE = false;

layout(std430, binding = 1) readonly buffer Directions { uint directions[]; };  // oas::sobolDirections()
#define OAS_SOBOL_DIRECTION(dim, bit) directions[(dim) * 32u + (bit)]
#include "oas/oas.glsl"

layout(local_size_x = 8) in;
layout(push_constant) uniform Params {
    OasPattern pattern;
    uint spp;
    uint dims;
    uint dimBase;
    uint mode;
    uint burn;
} params;
layout(std430, binding = 0) writeonly buffer Samples { float values[]; };

/// What CALIBRATE writes instead of a sample: loop-free, and different for every value.
float stand_in(uint seed, uint i, uint dim) { return float(oas_hash3(seed, i, dim) >> 8u) * OAS_INV_2POW24; }

void main()
{
    uint pixel = gl_GlobalInvocationID.x;
    uint seed = oas_pixel_seed(pixel, 7u, 0x5eedu);
    uint base = pixel * params.spp * params.dims;
    uint burnt = 0u;
    for (uint b = 0u; b < params.burn; ++b) burnt += b ^ seed;
    // Every lane writes its burn result past the samples, so the burn loop cannot be removed.
    values[gl_NumWorkGroups.x * 8u * params.spp * params.dims + pixel] = float(burnt & 1u);

    if (params.mode == 0u) {
        for (uint i = 0u; i < params.spp; ++i)
            for (uint d = 0u; d < params.dims; ++d) {
                uint dim = params.dimBase + d;
                values[base + i * params.dims + d] = CALIBRATE ? stand_in(seed, i, dim) : oas_sample(params.pattern, seed, i, dim);
            }
        return;
    }
    for (uint d = 0u; d < params.dims; ++d) {
        uint dim = params.dimBase + d;
        uint block = dim / params.pattern.blockDims;
        uint col = dim - block * params.pattern.blockDims;
        for (uint i = 0u; i < params.spp;) {
            if (CALIBRATE) {
                uint end = min(params.spp, (i / params.pattern.N + 1u) * params.pattern.N);
                for (; i < end; ++i) values[base + i * params.dims + d] = stand_in(seed, i, dim);
            } else {
                OasBlock b = oas_block(params.pattern, seed, i, block);
                OasColumn c = oas_column(params.pattern, b.seed, col);
                uint end = min(params.spp, b.firstIndex + params.pattern.N);
                for (; i < end; ++i) values[base + i * params.dims + d] = oas_column_dim(params.pattern, c, oas_block_row(b, i));
            }
        }
    }
}
