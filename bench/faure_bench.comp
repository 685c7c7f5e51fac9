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
#include "oas/oas.glsl"

layout(local_size_x = 64) in;
layout(push_constant) uniform Params {
    OasFaure faure;
    uint pixels;
    uint spp;
    uint dims;
    uint frameSeed;
} params;
layout(std430, binding = 0) writeonly buffer Values { float values[]; };

void main()
{
    uint at = gl_GlobalInvocationID.x;
    if (at >= params.pixels * params.spp) return;
    uint pixel = at / params.spp, sampleIndex = at - pixel * params.spp;
    uint pixelSeed = oas_pixel_seed(pixel, 0u, params.frameSeed);
    uint q = params.faure.field.q;
    for (uint d = 0u; d < params.dims; ++d) {
        uint blockIndex = d / q, element = d - blockIndex * q;
        values[at * params.dims + d] =
            oas_faure_value(params.faure, element, sampleIndex, oas_faure_key(pixelSeed, blockIndex, element));
    }
}
