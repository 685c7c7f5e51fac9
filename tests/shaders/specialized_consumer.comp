#version 450
// A consumer that specializes the include on one pattern kind, as docs/EMBEDDING.md advises (all
// six OAS_STATIC_* from specialization constants, filled by oas_specialization), and is then
// handed patterns of other kinds. One invocation per sample of one pixel writes `dims` values
// through oas_sample and the same dimensions through oas_draw. tests/specialization_test.cpp checks
// that a matching pattern gives the CPU twin's values bit for bit and any other gives NaN in every
// value, never numbers. Built a second time with -DCONSUMER_DRAW_BLOCKS=2 (OAS_STATIC_DRAW_BLOCKS 2):
// a draw within two blocks gives oas_sample's values, one past them NaN in every value.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(constant_id = 0) const uint specConstruction = 1u;
layout(constant_id = 1) const uint specOffset = 3u;
layout(constant_id = 2) const uint specFieldKind = 0u;
layout(constant_id = 3) const uint specFieldDegree = 1u;
layout(constant_id = 4) const uint specSmallN = 1u;
layout(constant_id = 5) const uint specIndexBits = 24u;
#define OAS_STATIC_CONSTRUCTION specConstruction
#define OAS_STATIC_OFFSET specOffset
#define OAS_STATIC_FIELD_KIND specFieldKind
#define OAS_STATIC_FIELD_DEGREE specFieldDegree
#define OAS_STATIC_SMALL_N specSmallN
#define OAS_STATIC_INDEX_BITS specIndexBits
#ifdef CONSUMER_DRAW_BLOCKS
#define OAS_STATIC_DRAW_BLOCKS CONSUMER_DRAW_BLOCKS
#endif

layout(std430, binding = 1) readonly buffer Directions { uint directions[]; };  // oas::sobolDirections()
#define OAS_SOBOL_DIRECTION(dim, bit) directions[(dim) * 32u + (bit)]
#include "oas/oas.glsl"

layout(local_size_x = 8) in;
layout(push_constant) uniform Params {
    OasPattern pattern;
    uint spp;
    uint dims;  // <= OAS_DRAW_MAX
    uint seed;  // the pixel seed
    uint firstDim;  // the first dimension written
} params;
layout(std430, binding = 0) writeonly buffer Values { float values[]; };  // [sample][2][dims]

void main()
{
    uint index = gl_GlobalInvocationID.x;
    if (index >= params.spp) return;
    uint at = index * 2u * params.dims;
    for (uint d = 0u; d < params.dims; ++d) values[at + d] = oas_sample(params.pattern, params.seed, index, params.firstDim + d);
    OasDraw draw = oas_draw(params.pattern, params.seed, index, params.firstDim, params.dims);
    OAS_UNROLL for (uint k = 0u; k < OAS_DRAW_MAX; ++k)
        if (k < params.dims) values[at + params.dims + k] = draw.u[k];
}
