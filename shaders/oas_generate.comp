#version 450
// Writes the samples of (pixels x spp x dims) into a buffer, laid out [pixel][sample][dim] with
// pixel = y * width + x over a rectangle. One invocation per (pixel, sample, group of
// OAS_DIMS_PER_INVOCATION dims); the host dispatches chunks of items (firstItem, itemCount) so each
// dispatch stays within device limits. Groups keep each invocation's total loop count small:
// lavapipe (Mesa 22.3) silently stops a shader's loops after 65535 iterations in all.
// OAS_HASH_ONLY (a -D define) builds the same-shape kernel that only hashes: the benchmark's
// practical ceiling for a per-(sample, dim) stateless sampler.
#extension GL_GOOGLE_include_directive : require

// Specialised per pattern kind (the host sets these from the pattern), so the branches of the
// other constructions, offsets and field kinds fold away: lavapipe executes both sides of every
// branch, and unspecialised the kernel runs ~20x slower there.
layout(constant_id = 0) const uint oasSpecConstruction = 1u;
layout(constant_id = 1) const uint oasSpecOffset = 3u;
layout(constant_id = 2) const uint oasSpecFieldKind = 0u;
#define OAS_STATIC_CONSTRUCTION oasSpecConstruction
#define OAS_STATIC_OFFSET oasSpecOffset
#define OAS_STATIC_FIELD_KIND oasSpecFieldKind
// The Sobol baseline's direction numbers (oas::sobolDirections(), 64 dims x 32 bits).
layout(std430, binding = 1) readonly buffer SobolDirections { uint sobolDirections[]; };
#define OAS_SOBOL_DIRECTION(dim, bit) sobolDirections[(dim) * 32u + (bit)]
#include "oas/oas.glsl"

layout(local_size_x = 64) in;
const uint OAS_DIMS_PER_INVOCATION = 8u;  // keep equal to kDimsPerInvocation in generate_gpu.cpp

layout(push_constant) uniform GenerateParams {
    OasPattern pattern;
    uint x0;
    uint y0;
    uint width;
    uint spp;
    uint dims;
    uint seed;
    uint firstItem;
    uint itemCount;
    uint firstSample;  // sample indices [firstSample, firstSample + spp)
} params;

layout(std430, binding = 0) writeonly buffer Samples { float values[]; };

void main()
{
    uint local = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (local >= params.itemCount) return;
    uint groups = (params.dims + OAS_DIMS_PER_INVOCATION - 1u) / OAS_DIMS_PER_INVOCATION;
    uint item = params.firstItem + local;     // item = (pixel * spp + sample) * groups + group
    uint pointItem = item / groups;
    uint group = item - pointItem * groups;
    uint pixel = pointItem / params.spp;
    uint index = params.firstSample + (pointItem - pixel * params.spp);
    uint py = pixel / params.width;
    uint seed = oas_pixel_seed(params.x0 + (pixel - py * params.width), params.y0 + py, params.seed);
    uint firstDim = group * OAS_DIMS_PER_INVOCATION;
    uint endDim = min(params.dims, firstDim + OAS_DIMS_PER_INVOCATION);
    // Output offset relative to the chunk: the chunk starts at a whole point (see generate_gpu.cpp).
    uint base = (pointItem - params.firstItem / groups) * params.dims;
#ifdef OAS_HASH_ONLY
    for (uint d = firstDim; d < endDim; ++d)
        values[base + d] = float(oas_hash3(seed, d, index) >> 8u) * OAS_INV_2POW24;
#else
    if (params.pattern.construction >= OAS_RANDOM) {
        for (uint d = firstDim; d < endDim; ++d) values[base + d] = oas_sample(params.pattern, seed, index, d);
        return;
    }
    // One row shuffle per OA block, shared by the block's dimensions (as generateCpu does).
    uint d = firstDim;
    while (d < endDim) {
        uint block = d / params.pattern.blockDims;
        OasRow row = oas_row(params.pattern, seed, index, block);
        uint blockEnd = min(endDim, (block + 1u) * params.pattern.blockDims);
        for (; d < blockEnd; ++d) values[base + d] = oas_row_dim(params.pattern, row, d - block * params.pattern.blockDims);
    }
#endif
}
