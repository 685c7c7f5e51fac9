#version 450
// Writes the samples of (pixels x spp x dims) into a buffer, laid out [pixel][sample][dim] with
// pixel = y * width + x over a rectangle. One invocation per (pixel, run of samplesPerRun
// consecutive samples, group of up to OAS_GROUP_DIMS dims of one OA block, or one pair of a
// padded 2D baseline): the block and column state (OasBlock, OasColumn: seeds, permutation keys,
// field constants; OasPairColumn for the pairs) is made once per pass and reused by every sample
// of the run, which is the library's fast path. The other baselines take a run x
// baselineGroupDims of the dimensions the caller reads (unreadDims), one dimension at a time, its
// state (OasSobolColumn, OasHaltonColumn) once per pass. The host dispatches
// chunks of whole runs (firstItem, itemCount) so each dispatch stays within device limits. The
// library's loops all unroll, so a run's loop iterations are this kernel's own, far below
// lavapipe's silent cap of 65535 (generate_gpu.cpp, samplesPerRun).
// OAS_HASH_ONLY (a -D define) builds the same-shape kernel that only hashes: the benchmark's
// practical ceiling for a per-(sample, dim) stateless sampler.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// Specialised per pattern kind (the host sets these from the pattern), so the branches of the
// other constructions, offsets and field kinds fold away: lavapipe executes both sides of every
// branch. OAS_UNSPECIALISED (a -D define) builds the kernel without them, for the benchmark's
// figure of what specialisation buys (docs/BENCHMARKS.md).
#ifndef OAS_UNSPECIALISED
layout(constant_id = 0) const uint oasSpecConstruction = 1u;
layout(constant_id = 1) const uint oasSpecOffset = 3u;
layout(constant_id = 2) const uint oasSpecFieldKind = 0u;
layout(constant_id = 3) const uint oasSpecFieldDegree = 1u;
layout(constant_id = 4) const uint oasSpecSmallN = 0u;
layout(constant_id = 5) const uint oasSpecIndexBits = 24u;
#define OAS_STATIC_CONSTRUCTION oasSpecConstruction
#define OAS_STATIC_OFFSET oasSpecOffset
#define OAS_STATIC_FIELD_KIND oasSpecFieldKind
#define OAS_STATIC_FIELD_DEGREE oasSpecFieldDegree
#define OAS_STATIC_SMALL_N oasSpecSmallN
#define OAS_STATIC_INDEX_BITS oasSpecIndexBits
#endif
// The Sobol baselines' direction numbers (oas::sobolDirections(), 1024 dims x 32 bits), as texels
// of four (lavapipe fetches texels for all lanes at once; see pt_render.comp).
layout(binding = 1) uniform usamplerBuffer sobolTexels;
#define OAS_SOBOL_DIRECTION(dim, bit) texelFetch(sobolTexels, int((dim) * 8u + (bit) / 4u))[(bit) & 3u]
#include "oas/oas.glsl"

layout(local_size_x = 64) in;
const uint OAS_GROUP_DIMS = 4u;  // OA constructions; keep equal to kGroupDims in generate_gpu.cpp

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
    uint firstSample;    // sample indices [firstSample, firstSample + spp)
    uint samplesPerRun;  // samples one invocation evaluates
    uint groupsPerBlock; // OAs: ceil(min(blockDims, dims) / OAS_GROUP_DIMS); baselines: 0
    uint groups;         // dimension groups per (pixel, run)
    uint chunkFirstPoint;  // pixel * spp + sample of the chunk's first output point
    uint baselineGroupDims;  // baselines: made dims per group (generate_gpu.cpp's balanced split)
    uint unreadDims;         // baselines: bit d (d < 32) set, dimension d is not made (a caller's gaps)
} params;

// The output as a storage texel buffer of uint: lavapipe stores a texel for all lanes at once,
// where it writes a storage-buffer element whose index differs across lanes one lane at a time.
layout(binding = 0, r32ui) uniform writeonly uimageBuffer valueTexels;
#define OAS_WRITE(at, value) imageStore(valueTexels, int(at), uvec4(floatBitsToUint(value)))

#ifdef OAS_HASH_ONLY
/// Dimension `dim` of `count` samples from `index`, written from element outAt every params.dims:
/// one hash a value, the baselines' shape.
void generate_baseline_dim(uint seed, uint index, uint count, uint outAt, uint dim)
{
    for (uint k = 0u; k < count; ++k, ++index, outAt += params.dims)
        OAS_WRITE(outAt, float(oas_hash3(seed, dim, index) >> 8u) * OAS_INV_2POW24);
}
void generate_pair(uint seed, uint index, uint count, uint outAt, uint firstDim, uint groupDims)
{
    generate_baseline_dim(seed, index, count, outAt, firstDim);
    if (groupDims > 1u) generate_baseline_dim(seed, index, count, outAt + 1u, firstDim + 1u);
}
#else
// Not oas_draw, here: its loop over OAS_DRAW_MAX dimensions unrolls, so the sampler would be
// compiled in eight times where main's run-time loop over a group's dimensions has it once, for
// no gain (a baseline has no state to share across dimensions; the values are the same).

/// The padded 2D baselines' fast path: one pair (firstDim is even; groupDims 1 where the pair
/// is cut by the request's last dimension), `count` samples from `index` written from element
/// outAt every params.dims, the pair's state once per pass and its cell once per sample.
void generate_pair(uint seed, uint index, uint count, uint outAt, uint firstDim, uint groupDims)
{
    while (count != 0u) {  // a run may cross the end of a pass (a multiple of N)
        uint pass = oas_div_n(params.pattern, index);
        uint passSeed = oas_pass_seed(seed, pass);
        uint inPass = min(count, params.pattern.N - (index - pass * params.pattern.N));
        OasPairColumn x = oas_pair_column(params.pattern, passSeed, firstDim);
        OasPairColumn y = oas_pair_column(params.pattern, passSeed, firstDim + 1u);
        for (uint k = 0u; k < inPass; ++k, ++index, outAt += params.dims) {
            uint i = index - pass * params.pattern.N;
            uint cell = oas_pair_cell(x, i);
            OAS_WRITE(outAt, oas_pair_cell_dim(params.pattern, x, cell, i));
            if (groupDims > 1u) OAS_WRITE(outAt + 1u, oas_pair_cell_dim(params.pattern, y, cell, i));
        }
        count -= inPass;
    }
}

/// The other baselines: dimension `dim` of `count` samples from `index`, written from element
/// outAt every params.dims. Runs of samples of one dimension: its state once per pass
/// (OasSobolColumn: direction numbers and seeds; OasHaltonColumn: the base's constants and every
/// digit's permutation), where oas_sample makes it again for every value; random and
/// sobol-burley (no per-dimension state) find the pass and its seed once per pass (one sample per
/// invocation spent most of its time finding its pixel and pass: random ran at 0.6x the OAs'
/// values per second on lavapipe).
void generate_baseline_dim(uint seed, uint index, uint count, uint outAt, uint dim)
{
    bool tableSobol = OAS_CONSTRUCTION(params.pattern) == OAS_SOBOL || OAS_CONSTRUCTION(params.pattern) == OAS_SOBOL_OWEN;
    while (count != 0u) {  // a run may cross the end of a pass (a multiple of N)
        uint pass = oas_div_n(params.pattern, index);
        uint passSeed = oas_pass_seed(seed, pass);
        uint first = index - pass * params.pattern.N;
        uint inPass = min(count, params.pattern.N - first);
        if (tableSobol) {
            OasSobolColumn column = oas_sobol_column(passSeed, dim);
            for (uint k = 0u; k < inPass; ++k)
                OAS_WRITE(outAt + k * params.dims, oas_sobol_column_dim(params.pattern, column, first + k));
        } else if (OAS_CONSTRUCTION(params.pattern) == OAS_HALTON) {
            OasHaltonColumn column = oas_halton_column(params.pattern, passSeed, dim);
            // Block 0's indices are the samples' own, so each follows the last by a carry
            // (oas_halton_cursor_next) rather than two divisions per digit. The branch stands
            // outside the loops: lavapipe runs both sides of a branch, but a loop whose lanes are
            // all off ends after one masked pass.
            if (column.block == 0u) {
                OasHaltonCursor r = oas_halton_cursor(column, first);
                for (uint k = 0u; k < inPass; ++k, r = oas_halton_cursor_next(column, r))
                    OAS_WRITE(outAt + k * params.dims, oas_halton_cursor_value(params.pattern, column, r, first + k));
            } else {
                for (uint k = 0u; k < inPass; ++k)
                    OAS_WRITE(outAt + k * params.dims, oas_halton_column_dim(params.pattern, column, first + k));
            }
        } else {
            for (uint k = 0u; k < inPass; ++k)
                OAS_WRITE(outAt + k * params.dims, oas_baseline_dim(params.pattern, passSeed, first + k, dim));
        }
        index += inPass;
        outAt += inPass * params.dims;
        count -= inPass;
    }
}
#endif

// The baselines make only the dimensions a caller reads: `made` has bit d set for each dimension
// d < 32 to make (every dimension from 32 on is made). With step 1, the j-th made dimension; with
// step 2 (the padded 2D baselines' pairs, `made` then holding the even first dimensions of the
// pairs with a made dimension), the first dimension of the j-th made pair. Why: a path tracer
// fetches dimensions no path uses (an alignment gap, a last vertex's group the path ends before
// reading, the padding to whole texels); on blue_spheres9d 3 of the 12 it prefetches.
uint nth_made_dim(uint made, uint j, uint step)
{
    uint low = uint(bitCount(made));
    if (j >= low) return 32u + (j - low) * step;
    for (uint i = 0u; i < j; ++i) made &= made - 1u;  // clears the j lowest
    return uint(findLSB(made));
}

void main()
{
    uint local = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (local >= params.itemCount) return;
    uint runs = (params.spp + params.samplesPerRun - 1u) / params.samplesPerRun;
    uint item = params.firstItem + local;  // item = (pixel * runs + run) * groups + group
    uint pixelRun = item / params.groups;
    uint group = item - pixelRun * params.groups;
    uint pixel = pixelRun / runs;
    uint run = pixelRun - pixel * runs;
    uint py = pixel / params.width;
    uint seed = oas_pixel_seed(params.x0 + (pixel - py * params.width), params.y0 + py, params.seed);
    uint firstRunSample = run * params.samplesPerRun;  // relative to params.firstSample
    uint count = min(params.samplesPerRun, params.spp - firstRunSample);
    // Output offset of the run's first point relative to the chunk, which starts at a whole run
    // (see generate_gpu.cpp).
    uint runAt = (pixel * params.spp + firstRunSample - params.chunkFirstPoint) * params.dims;
    uint index = params.firstSample + firstRunSample;
    if (params.groupsPerBlock == 0u) {  // the baselines (the hash-only kernel too, given a baseline)
        uint made = (params.dims >= 32u ? ~0u : (1u << params.dims) - 1u) & ~params.unreadDims;
        uint past32 = max(params.dims, 32u) - 32u;
        if (oas_is_padded_2d(params.pattern)) {  // a pair a group (generate_gpu.cpp)
            made = (made | (made >> 1u)) & 0x55555555u;
            if (group >= uint(bitCount(made)) + (past32 + 1u) / 2u) return;
            uint firstDim = nth_made_dim(made, group, 2u);
            generate_pair(seed, index, count, runAt + firstDim, firstDim, min(2u, params.dims - firstDim));
            return;
        }
        uint first = group * params.baselineGroupDims;  // the group's first made dimension, counted
        uint madeDims = uint(bitCount(made)) + past32;
        if (first >= madeDims) return;
        uint groupDims = min(params.baselineGroupDims, madeDims - first);
        for (uint c = 0u; c < groupDims; ++c) {
            uint dim = nth_made_dim(made, first + c, 1u);
            generate_baseline_dim(seed, index, count, runAt + dim, dim);
        }
        return;
    }
    // The OAs: dimensions [firstDim, firstDim + groupDims) of one OA block, all made (the block's
    // row, made per sample, serves the group's columns).
    uint block = group / params.groupsPerBlock;
    uint blockDims = params.pattern.blockDims;
    uint firstCol = (group - block * params.groupsPerBlock) * OAS_GROUP_DIMS;
    uint firstDim = block * blockDims + firstCol;
    if (firstDim >= params.dims || firstCol >= blockDims) return;
    uint groupDims = min(OAS_GROUP_DIMS, min(blockDims - firstCol, params.dims - firstDim));
    uint outAt = runAt + firstDim;
#ifdef OAS_HASH_ONLY
    for (uint c = 0u; c < groupDims; ++c) generate_baseline_dim(seed, index, count, outAt + c, firstDim + c);
#else
    // A run may cross the end of a pass (a multiple of N); the state is remade for each pass.
    while (count != 0u) {
        OasBlock b = oas_block(params.pattern, seed, index, block);
        uint inPass = min(count, params.pattern.N - (index - b.firstIndex));
        // Four columns in named variables rather than an array: a run-time indexed local array
        // is a memory gather on lavapipe. Four rather than two (the block's row, made per sample,
        // serves four values) made Bose q=11 CMJ 1.22x faster on lavapipe and the pipeline build
        // 0.8 -> 1.3 s; eight, another 1.1x for a 2.5 s build.
        OasColumn c0 = oas_column(params.pattern, b.seed, firstCol);
        OasColumn c1 = oas_column(params.pattern, b.seed, min(firstCol + 1u, blockDims - 1u));
        OasColumn c2 = oas_column(params.pattern, b.seed, min(firstCol + 2u, blockDims - 1u));
        OasColumn c3 = oas_column(params.pattern, b.seed, min(firstCol + 3u, blockDims - 1u));
        for (uint k = 0u; k < inPass; ++k, ++index, outAt += params.dims) {
            OasRow r = oas_block_row(b, index);
            OAS_WRITE(outAt, oas_column_dim(params.pattern, c0, r));
            if (groupDims > 1u) OAS_WRITE(outAt + 1u, oas_column_dim(params.pattern, c1, r));
            if (groupDims > 2u) OAS_WRITE(outAt + 2u, oas_column_dim(params.pattern, c2, r));
            if (groupDims > 3u) OAS_WRITE(outAt + 3u, oas_column_dim(params.pattern, c3, r));
        }
        count -= inPass;
    }
#endif
}
