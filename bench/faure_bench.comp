#version 450
// oas-bench --faure: the progressive sampler's values (oas_faure_value) for a row of pixels, one
// invocation per (pixel, sample) making every dimension, written as the generation kernel writes
// values ([pixel][sample][dim]), so the figure compares with its Bose CMJ row. Compiled for a
// prime field (OAS_STATIC_FIELD_KIND / _DEGREE, as a specialised Bose pipeline is): the bench's
// bases are primes.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#define OAS_NO_SOBOL
#define OAS_STATIC_FIELD_KIND 0u
#define OAS_STATIC_FIELD_DEGREE 1u
// FAURE_BENCH_STATIC_DIGITS (the second build of this file): K, the sequence's digit count, fixed
// by specialization constant 0; the first build leaves K to run time and ignores the constant.
layout(constant_id = 0) const uint faureDigits = 0u;
#ifdef FAURE_BENCH_STATIC_DIGITS
#define OAS_STATIC_FAURE_DIGITS faureDigits
#define OAS_STATIC_SMALL_N 1u  // every row has q^K <= 2^16: the stratum point's short division
#endif
#include "oas/oas.glsl"

layout(local_size_x = 64) in;
layout(push_constant) uniform Params {
    OasFaure faure;
    uint pixels;
    uint spp;
    uint dims;
    uint frameSeed;
} params;
// Written through a storage texel buffer, as the generation kernel writes its values: lavapipe
// stores texels for all lanes at once, storage-buffer elements one lane at a time.
layout(binding = 0, r32ui) uniform writeonly uimageBuffer valueTexels;

void main()
{
    uint at = gl_GlobalInvocationID.x;
    if (at >= params.pixels * params.spp) return;
    uint pixel = at / params.spp, sampleIndex = at - pixel * params.spp;
    uint pixelSeed = oas_pixel_seed(pixel, 0u, params.frameSeed);
    uint q = params.faure.field.q;
    for (uint d = 0u; d < params.dims; ++d) {
        uint blockIndex = d / q, element = d - blockIndex * q;
        float v = oas_faure_value(params.faure, element, sampleIndex, oas_faure_key(pixelSeed, blockIndex, element));
        imageStore(valueTexels, int(at * params.dims + d), uvec4(floatBitsToUint(v)));
    }
}
