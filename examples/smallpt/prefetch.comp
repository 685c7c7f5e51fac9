#version 450
// The prefetch recipe (docs/EMBEDDING.md): dispatched before each tracer dispatch, it writes the
// values of the tracer's next `samples` samples. One invocation per (pixel, group of GROUP or
// fewer consecutive dimensions of one OA block) makes the block's state and the group's column states
// once per pass (oas_block, oas_column) and each sample's row once for the whole group
// (oas_block_row), so a value costs only oas_column_dim; baselines, which have no blocks, go
// through oas_prefetch one dimension at a time. Output: [pixel][sample - firstSample][dim], the
// layout smallpt.comp reads. smallpt.cpp's prefetchWidth picks GROUP, and prefetchGroups counts
// the groups the same way as main() below.
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

/// Dimensions one invocation writes, at most 8 (a path vertex's draw, OAS_DRAW_MAX): more would
/// hold more column states per lane, fewer would make each sample's row for fewer values. The
/// host picks it so that a block's groups are as even as they can be (9 columns: 5 and 4, not 8
/// and 1): lavapipe runs the loops below GROUP times whatever a group's own count, so a short
/// group costs a full one.
layout(constant_id = 5) const uint GROUP = 8u;

void main()
{
    // Invocation -> (pixel, block, the group's first column). Baselines have no blocks (their
    // blockDims is not a divisor): their groups are runs of GROUP dimensions.
    bool baseline = OAS_CONSTRUCTION(params.pattern) >= OAS_RANDOM;
    uint span = baseline ? GROUP : params.pattern.blockDims;  // dimensions a block holds
    uint groupsPerBlock = (span + GROUP - 1u) / GROUP;
    uint fullBlocks = params.dims / span, rest = params.dims - fullBlocks * span;
    uint groups = fullBlocks * groupsPerBlock + (rest + GROUP - 1u) / GROUP;  // per pixel; a partial block last
    uint item = gl_GlobalInvocationID.x;
    uint pixel = item / groups, group = item - pixel * groups;
    if (pixel >= params.width * params.height) return;
    uint block = group / groupsPerBlock, firstCol = (group - block * groupsPerBlock) * GROUP;
    uint firstDim = block * span + firstCol;
    uint count = min(GROUP, min(span - firstCol, params.dims - firstDim));  // >= 1
    uint y = pixel / params.width;
    uint seed = oas_pixel_seed(pixel - y * params.width, y, params.frameSeed);
    uint dest = pixel * params.samples * params.dims + firstDim;  // where sample 0's first value goes
    if (baseline) {
        [[unroll]] for (uint j = 0u; j < GROUP; ++j)
            if (j < count)
                oas_prefetch(params.pattern, seed, firstDim + j, params.firstSample, params.samples, dest + j, params.dims);
        return;
    }
    uint k = 0u;
    while (k < params.samples) {  // one pass of the run per iteration
        uint index = params.firstSample + k;
        OasBlock b = oas_block(params.pattern, seed, index, block);
        OasColumn columns[GROUP];
        // Columns past count repeat the last one (made but not stored): no branch on count here.
        [[unroll]] for (uint j = 0u; j < GROUP; ++j)
            columns[j] = oas_column(params.pattern, b.seed, firstCol + min(j, count - 1u));
        uint end = min(params.samples, b.firstIndex + params.pattern.N - params.firstSample);  // the pass's end, as k
        for (; k < end; ++k) {
            OasRow row = oas_block_row(b, params.firstSample + k);
            [[unroll]] for (uint j = 0u; j < GROUP; ++j)
                if (j < count) OAS_PREFETCH_STORE(dest + k * params.dims + j, oas_column_dim(params.pattern, columns[j], row));
        }
    }
}
