#version 450
// The prefetch recipe (docs/EMBEDDING.md): dispatched before each tracer dispatch, one invocation
// per (pixel, dimension), it writes the values of the tracer's next `samples` samples through
// oas_prefetch, which makes the OA block's and column's state once per pass instead of once per
// value. Output: [pixel][sample - firstSample][dim], the layout smallpt.comp reads.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(constant_id = 0) const uint specConstruction = 1u;
layout(constant_id = 1) const uint specOffset = 3u;
layout(constant_id = 2) const uint specFieldKind = 0u;
layout(constant_id = 3) const uint specFieldDegree = 1u;
layout(constant_id = 4) const uint specSmallN = 1u;
#define OAS_STATIC_CONSTRUCTION specConstruction
#define OAS_STATIC_OFFSET specOffset
#define OAS_STATIC_FIELD_KIND specFieldKind
#define OAS_STATIC_FIELD_DEGREE specFieldDegree
#define OAS_STATIC_SMALL_N specSmallN
#define OAS_NO_SOBOL
// Where oas_prefetch writes: one uint texel per value (lavapipe stores texels for all lanes at once).
layout(binding = 0, r32ui) uniform writeonly uimageBuffer values;
#define OAS_PREFETCH_STORE(at, v) imageStore(values, int(at), uvec4(floatBitsToUint(v)))
#include "oas/oas.glsl"

layout(local_size_x = 64) in;
layout(push_constant) uniform Params {
    OasPattern pattern;
    uint width;
    uint height;
    uint frameSeed;
    uint firstSample;
    uint samples;
    uint dims;
} params;

void main()
{
    uint item = gl_GlobalInvocationID.x;  // pixel * dims + dim
    uint pixel = item / params.dims, dim = item - pixel * params.dims;
    if (pixel >= params.width * params.height) return;
    uint y = pixel / params.width;
    uint seed = oas_pixel_seed(pixel - y * params.width, y, params.frameSeed);
    oas_prefetch(params.pattern, seed, dim, params.firstSample, params.samples, pixel * params.samples * params.dims + dim, params.dims);
}
