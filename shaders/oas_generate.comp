#version 450
// Writes the samples of (pixels x spp x dims) into a buffer, laid out [pixel][sample][dim] with
// pixel = y * width + x over a rectangle. One invocation per (pixel, run of samplesPerRun
// consecutive samples, group of up to OAS_GROUP_DIMS dims of one OA block, or one pair of a
// padded 2D baseline): the block and column state (OasBlock, OasColumn: seeds, permutation keys,
// field constants; OasPairColumn for the pairs) is made once per pass and reused by every sample
// of the run, which is the library's fast path. The other baselines take one sample x
// baselineGroupDims dims per invocation. The host dispatches
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
    uint baselineGroupDims;  // baselines: dims per group (kBaselineGroupDims)
} params;

// The output as a storage texel buffer of uint: lavapipe stores a texel for all lanes at once,
// where it writes a storage-buffer element whose index differs across lanes one lane at a time.
layout(binding = 0, r32ui) uniform writeonly uimageBuffer valueTexels;
#define OAS_WRITE(at, value) imageStore(valueTexels, int(at), uvec4(floatBitsToUint(value)))

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
    // Dimensions [firstDim, firstDim + groupDims): within one OA block for the OA constructions.
    uint block = 0u;
    uint groupSize = params.baselineGroupDims;
    uint firstCol = group * groupSize;
    uint blockDims = params.dims;
    if (params.groupsPerBlock != 0u) {  // OA constructions (the hash-only kernel is not specialised)
        block = group / params.groupsPerBlock;
        groupSize = OAS_GROUP_DIMS;
        firstCol = (group - block * params.groupsPerBlock) * OAS_GROUP_DIMS;
        blockDims = params.pattern.blockDims;
    }
    uint firstDim = block * blockDims + firstCol;
    if (firstDim >= params.dims || firstCol >= blockDims) return;
    uint groupDims = min(groupSize, min(blockDims - firstCol, params.dims - firstDim));
    uint firstRunSample = run * params.samplesPerRun;  // relative to params.firstSample
    uint count = min(params.samplesPerRun, params.spp - firstRunSample);
    // Output offset relative to the chunk, which starts at a whole run (see generate_gpu.cpp).
    uint outAt = (pixel * params.spp + firstRunSample - params.chunkFirstPoint) * params.dims + firstDim;
    uint index = params.firstSample + firstRunSample;
#ifdef OAS_HASH_ONLY
    for (uint k = 0u; k < count; ++k, ++index, outAt += params.dims)
        for (uint c = 0u; c < groupDims; ++c)
            OAS_WRITE(outAt + c, float(oas_hash3(seed, firstDim + c, index) >> 8u) * OAS_INV_2POW24);
#else
    // Not oas_draw, here: its loop over OAS_DRAW_MAX dimensions unrolls, so the sampler would be
    // compiled in eight times where this run-time loop has it once, for no gain (a baseline has no
    // state to share across dimensions; the values are the same). The OA path below is the
    // library's bulk fast path: block and column state once per pass, shared by the run's
    // samples, which oas_draw (one sample a call) would make again for every sample.
    if (oas_is_padded_2d(params.pattern)) {
        // The padded 2D baselines' fast path: one pair (firstDim is even), runs of samples, the
        // pair's state once per pass and its cell once per sample (generate_gpu.cpp's layout).
        while (count != 0u) {
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
        return;
    }
    bool tableSobol = OAS_CONSTRUCTION(params.pattern) == OAS_SOBOL || OAS_CONSTRUCTION(params.pattern) == OAS_SOBOL_OWEN;
    if (tableSobol || OAS_CONSTRUCTION(params.pattern) == OAS_HALTON) {
        // Runs of samples, one dimension at a time: its state once per (pass, dimension)
        // (OasSobolColumn: direction numbers and seeds; OasHaltonColumn: the base's constants and
        // every digit's permutation), where oas_sample makes it again for every value.
        while (count != 0u) {
            uint pass = oas_div_n(params.pattern, index);
            uint passSeed = oas_pass_seed(seed, pass);
            uint first = index - pass * params.pattern.N;
            uint inPass = min(count, params.pattern.N - first);
            for (uint c = 0u; c < groupDims; ++c) {
                if (tableSobol) {
                    OasSobolColumn column = oas_sobol_column(passSeed, firstDim + c);
                    for (uint k = 0u; k < inPass; ++k)
                        OAS_WRITE(outAt + k * params.dims + c, oas_sobol_column_dim(params.pattern, column, first + k));
                } else {
                    OasHaltonColumn column = oas_halton_column(params.pattern, passSeed, firstDim + c);
                    // Block 0's indices are the samples' own, so each follows the last by a carry
                    // (oas_halton_cursor_next) rather than two divisions per digit. The branch
                    // stands outside the loops: lavapipe runs both sides of a branch, but a loop
                    // whose lanes are all off ends after one masked pass.
                    if (column.block == 0u) {
                        OasHaltonCursor r = oas_halton_cursor(column, first);
                        for (uint k = 0u; k < inPass; ++k, r = oas_halton_cursor_next(column, r))
                            OAS_WRITE(outAt + k * params.dims + c, oas_halton_cursor_value(params.pattern, column, r, first + k));
                    } else {
                        for (uint k = 0u; k < inPass; ++k)
                            OAS_WRITE(outAt + k * params.dims + c, oas_halton_column_dim(params.pattern, column, first + k));
                    }
                }
            }
            index += inPass;
            outAt += inPass * params.dims;
            count -= inPass;
        }
        return;
    }
    if (OAS_CONSTRUCTION(params.pattern) >= OAS_RANDOM) {
        // Random and sobol-burley (no per-dimension state) take runs of samples, as the OAs do:
        // the pass and its seed once per pass, then the value. One sample per invocation spent
        // most of its time finding its pixel and pass (random ran at 0.6x the OAs' values per
        // second on lavapipe).
        while (count != 0u) {
            uint pass = oas_div_n(params.pattern, index);
            uint passSeed = oas_pass_seed(seed, pass);
            uint inPass = min(count, params.pattern.N - (index - pass * params.pattern.N));
            for (uint k = 0u; k < inPass; ++k, ++index, outAt += params.dims)
                for (uint c = 0u; c < groupDims; ++c)
                    OAS_WRITE(outAt + c, oas_baseline_dim(params.pattern, passSeed, index - pass * params.pattern.N, firstDim + c));
            count -= inPass;
        }
        return;
    }
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
