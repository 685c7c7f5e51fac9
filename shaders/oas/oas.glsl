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
//
// API
//   struct OasPattern            64-byte descriptor; make it on the host with oas::makePattern
//                                (C++), which checks the parameters, and upload it (push constant
//                                or uniform/storage buffer; its layout is 16 uints).
//   uint  oas_pixel_seed(uint x, uint y, uint seed)              per-pixel seed
//   float oas_sample(OasPattern p, uint pixelSeed, uint index, uint dim)
//         Dimension `dim` of sample `index` of the pixel: a pure function, O(1) work, in [0, 1)
//         (never 1.0, never NaN), exactly inside the strata the construction promises.
//   OasRow oas_row(OasPattern p, uint pixelSeed, uint index, uint block)
//   float  oas_row_dim(OasPattern p, OasRow r, uint col)
//         The same values, faster when you consume many dimensions of one OA block: dimension
//         block * p.blockDims + col. (oas_sample = oas_row + oas_row_dim, or the baselines.)
//
// EXAMPLE (another renderer's path-tracing shader: one invocation per pixel and sample)
//   #extension GL_GOOGLE_include_directive : require
//   #include "oas/oas.glsl"
//   layout(push_constant) uniform Params { OasPattern pattern; uint frameSeed; uint spp; } params;
//   ...
//   uint pixel = gl_GlobalInvocationID.x, s = gl_GlobalInvocationID.y;   // s < params.spp
//   uint seed = oas_pixel_seed(pixel % width, pixel / width, params.frameSeed);
//   vec2 pixelJitter = vec2(oas_sample(params.pattern, seed, s, 0u),
//                           oas_sample(params.pattern, seed, s, 1u));
//   vec2 lensUV      = vec2(oas_sample(params.pattern, seed, s, 2u),
//                           oas_sample(params.pattern, seed, s, 3u));
//   ...
//   Put paired dimensions on partner columns (0,1), (2,3), ... : Bose CMJ correlates those pairs.
//   Give each sample its own invocation (or a few per invocation). Today's permutations loop
//   (cycle walking, a data-dependent count), and lavapipe silently ends every invocation's loops
//   after 65535 iterations in total: one invocation looping over 121 samples x 12 dims returned
//   zeros from sample 33 on. Fetch the dimensions you need at one call site (a loop over them),
//   not at every use: GPU compilers inline the whole sampler wherever it is called, which made a
//   path tracer's pipeline build take 20 s on lavapipe instead of 1.5 s (shaders/pt/pt_trace.glsl,
//   pt_group_dims).
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

/// Dimension `dim` of sample `index` for the pixel with seed `pixelSeed`. See the API above.
float oas_sample(OasPattern pat, uint pixelSeed, uint index, uint dim)
{
    if (OAS_CONSTRUCTION(pat) >= OAS_RANDOM) {
        uint seed = pixelSeed;
        uint pass = oas_div_n(pat, index);
        if (pass != 0u) {
            index -= pass * pat.N;
            seed = oas_hash3(pixelSeed, pass, OAS_TAG_PASS);
        }
        return oas_baseline_dim(pat, seed, index, dim);
    }
    uint block = dim / pat.blockDims;
    OasRow r = oas_row(pat, pixelSeed, index, block);
    return oas_row_dim(pat, r, dim - block * pat.blockDims);
}

#endif // OAS_GLSL
