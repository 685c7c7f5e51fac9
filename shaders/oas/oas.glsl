// oas.glsl - Orthogonal Array Sampling for Monte Carlo rendering: the embeddable GLSL library.
//
// Implements Jarosz, Enayet, Kensler, Kilpatrick and Christensen, "Orthogonal Array Sampling for
// Monte Carlo Rendering" (EGSR 2019): randomized orthogonal arrays (Bose, Bush, Bose-Bush,
// Addelman-Kempthorne, CMJND) with centered / J / MJ / CMJ offsets, which stratify every
// t-dimensional projection of a high-dimensional sample set; plus baseline samplers (independent,
// jittered-2D and CMJ-2D padded, Owen-scrambled (0,2) padded, randomized Halton).
//
// EMBEDDING
//   The file has no #version, no bindings and no extension requirements of its own; including it
//   needs GL_GOOGLE_include_directive (or paste the files in). Every public name starts with
//   oas_, Oas or OAS_. It is plain GLSL 4.50 integer code: no 64-bit types, no float division.
//   The same files compile as C++ (host/oas/glsl_compat.hpp), so the CPU reference is this code.
//   Before including, define either OAS_SOBOL_DIRECTION(dim, bit) (the Sobol baseline reads its
//   direction numbers through it: oas::sobolDirections() on the host, in a buffer) or
//   OAS_NO_SOBOL (the shader never receives a Sobol pattern); with neither it is a compile error.
//   Targets without umulExtended may define OAS_MULHI(a, b), e.g. as oas_mulhi_portable.
//   Macros: the library's struct members, parameters and locals are short names, so an
//   object-like macro of the includer with one of these names, defined before the include,
//   breaks it (tests/embedding_test.cpp checks this list against glslangValidator):
//     N K i j k l m n p q r s t u v x y seed index offset dim pass row col level block key hi lo
//     bits mask shift f g a b c d e h sub rotation pivot partner stratum jitter base digit power
//     construction strength aux fieldP
//   Undefine them around the include, or include oas.glsl first.
//
// API
//   struct OasPattern            64-byte descriptor; make it on the host with oas::makePattern
//                                (C++), which checks the parameters, and upload it (push constant
//                                or uniform/storage buffer; its layout is 16 uints).
//   uint  oas_pixel_seed(uint x, uint y, uint seed)              per-pixel seed
//   float oas_sample(OasPattern p, uint pixelSeed, uint index, uint dim)
//         Dimension `dim` of sample `index` of the pixel: a pure function, fixed work, in [0, 1)
//         (never 1.0, never NaN), exactly inside the strata the construction promises.
//   The same values, faster, from state made once and reused (the fast path):
//   OasRow    oas_row(OasPattern p, uint pixelSeed, uint index, uint block)
//   float     oas_row_dim(OasPattern p, OasRow r, uint col)
//         per (sample, block), reused across the block's dimensions: dimension
//         block * p.blockDims + col (oas_sample = oas_row + oas_row_dim, or the baselines);
//   OasBlock  oas_block(OasPattern p, uint pixelSeed, uint index, uint block)
//   OasColumn oas_column(OasPattern p, uint blockSeed, uint col)       blockSeed = OasBlock.seed
//   OasRow    oas_block_row(OasBlock b, uint index)
//   float     oas_column_dim(OasPattern p, OasColumn c, OasRow r)
//         per (pixel, pass, block) and per (pixel, pass, block, column), reused across the N
//         samples of a pass (indices [b.firstIndex, b.firstIndex + N)): seeds, permutation keys
//         and field constants are made once, and each further value costs only its own work.
//   OA constructions only (construction < OAS_RANDOM); baselines go through oas_sample.
//
// EXAMPLE 1 (another renderer's path-tracing shader: one invocation per pixel and sample)
//   #extension GL_GOOGLE_include_directive : require
//   #define OAS_NO_SOBOL
//   #include "oas/oas.glsl"
//   layout(push_constant) uniform Params { OasPattern pattern; uint frameSeed; uint spp; } params;
//   ...
//   uint pixel = gl_GlobalInvocationID.x, s = gl_GlobalInvocationID.y;   // s < params.spp
//   uint seed = oas_pixel_seed(pixel % width, pixel / width, params.frameSeed);
//   float u[4];                       // fetch the dimensions you need at one call site
//   OasRow row = oas_row(params.pattern, seed, s, 0u);           // dims 0..3 in block 0
//   for (uint d = 0u; d < 4u; ++d) u[d] = oas_row_dim(params.pattern, row, d);
//   vec2 pixelJitter = vec2(u[0], u[1]);
//   vec2 lensUV = vec2(u[2], u[3]);
//   (with p.blockDims < 4, or for baselines, use oas_sample(params.pattern, seed, s, d))
//
// EXAMPLE 2 (one invocation per pixel, looping over its samples: the per-pass state is hoisted)
//   OasBlock b = oas_block(params.pattern, seed, 0u, 0u);    // samples [0, N) of block 0
//   OasColumn c0 = oas_column(params.pattern, b.seed, 0u);
//   OasColumn c1 = oas_column(params.pattern, b.seed, 1u);
//   for (uint s = 0u; s < params.pattern.N; ++s) {
//       OasRow row = oas_block_row(b, s);
//       vec2 pixelJitter = vec2(oas_column_dim(params.pattern, c0, row), oas_column_dim(params.pattern, c1, row));
//       ...
//   }
//   (sample indices >= N begin a new pass: make its OasBlock and OasColumns for index N, 2N, ...)
//
// ADVICE
//   - Bose CMJ correlates the partner columns (0,1), (2,3), ...: each such pair is Kensler's
//     correlated multi-jitter, which converges like N^-1.5 on smooth integrands that differ
//     between opposite edges of the pair's square (N^-3 on periodic ones); MJ offsets give N^-2
//     on both (docs/STUDY.md). Prefer MJ for smooth, non-periodic pairs.
//   - Specialise the shader on the pattern kind (OAS_STATIC_CONSTRUCTION / _OFFSET / _FIELD_KIND,
//     e.g. from specialization constants, see oas_pattern.glsl). Lavapipe runs both sides of every
//     branch, so an unspecialised shader pays for every construction's code, loops included.
//   - Loops and lavapipe's cap. Lavapipe silently ends an invocation's loops after 65535
//     iterations in all. Specialised, the per-sample path of Bose and Addelman-Kempthorne over
//     prime fields, and of every permutation, is loop-free. The loops that remain have trip
//     counts fixed by the pattern, the same in every lane: Bush's t digits, CMJND's digit
//     extraction (up to d per value), binary-field products (k per product, several per value),
//     odd-extension-field arithmetic (~3k^2 per product) and the baselines' digit and bit loops
//     (Halton, Sobol, (0,2)). An invocation that evaluates many values of those patterns must
//     keep (values x loop iterations per value) under 65535. tests/loop_cap_test.cpp evaluates
//     8712 Bose values in one invocation.
//   - Fetch the dimensions you need at one call site (a loop over them), not at every use: GPU
//     compilers inline the whole sampler wherever it is called, which made a path tracer's
//     pipeline build take 20 s on lavapipe instead of 1.5 s (shaders/pt/pt_trace.glsl,
//     pt_group_dims).
//
// NUMERIC CONTRACT
//   Outputs are F * 2^-24 with integer F in [0, 2^24). A point promised to stratum m of K strata
//   (K = s for the OA levels, K = N for the MJ/CMJ Latin-hypercube property) satisfies
//   m/K <= x < (m+1)/K exactly, for K <= 2^24. All arithmetic is 32-bit unsigned and overflow-free
//   for the ranges the host accepts: N <= 2^24, fields q < 2^16 (Bose q <= 4096), any 32-bit
//   seed, pixel coordinate, dimension or sample index (index >= N starts a new randomized pass).
//
// MAX DIMENSIONS, STRENGTH AND LATIN-HYPERCUBE PROPERTY PER CONSTRUCTION
//   construction          N       dims/block  t   1D LHS (N strata) with offset
//   Bose                  q^2     q+1         2   MJ, CMJ
//   Bush                  q^t     q+1         t   MJ, CMJ
//   Bose-Bush (q=2^k)     2q^2    2q+1        2   MJ, CMJ
//   Addelman-Kempthorne   2q^2    2q+1        2   MJ, CMJ   (q odd)
//   CMJND                 s^d     d           d   MJ, CMJ
//   Centered and J offsets stratify 1D projections into s strata only. More dimensions than a
//   block holds use further, independently randomized blocks (padding by blocks).
#ifndef OAS_GLSL
#define OAS_GLSL

#include "oas_hash.glsl"
#include "oas_gf.glsl"
#include "oas_pattern.glsl"
#include "oas_oa.glsl"
#include "oas_baselines.glsl"

/// oas_sample for the baseline samplers alone (construction >= OAS_RANDOM): a caller that handles
/// the OA constructions through the fast path calls this for the rest, so the OA code is compiled
/// into its shader once, not twice.
float oas_baseline_sample(OasPattern pat, uint pixelSeed, uint index, uint dim)
{
    uint seed = pixelSeed;
    uint pass = oas_div_n(pat, index);
    if (pass != 0u) {
        index -= pass * pat.N;
        seed = oas_hash3(pixelSeed, pass, OAS_TAG_PASS);
    }
    return oas_baseline_dim(pat, seed, index, dim);
}

/// Dimension `dim` of sample `index` for the pixel with seed `pixelSeed`. See the API above.
float oas_sample(OasPattern pat, uint pixelSeed, uint index, uint dim)
{
    if (OAS_CONSTRUCTION(pat) >= OAS_RANDOM) return oas_baseline_sample(pat, pixelSeed, index, dim);
    uint block = dim / pat.blockDims;
    OasRow r = oas_row(pat, pixelSeed, index, block);
    return oas_row_dim(pat, r, dim - block * pat.blockDims);
}

#endif // OAS_GLSL
