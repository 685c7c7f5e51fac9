// oas.glsl - Orthogonal Array Sampling for Monte Carlo rendering: the embeddable GLSL library.
//
// Implements Jarosz, Enayet, Kensler, Kilpatrick and Christensen, "Orthogonal Array Sampling for
// Monte Carlo Rendering" (EGSR 2019): randomized orthogonal arrays (Bose, Bush, Bose-Bush,
// Addelman-Kempthorne, CMJND) with centered / J / MJ / CMJ offsets, which stratify every
// t-dimensional projection of a high-dimensional sample set; plus baseline samplers (independent,
// jittered-2D and CMJ-2D padded, Owen-scrambled (0,2) padded, randomized Halton).
//
// EMBEDDING
//   The file has no #version and no bindings. The including shader enables two extensions:
//     #extension GL_GOOGLE_include_directive : require      (to #include it; or paste the files in)
//     #extension GL_EXT_control_flow_attributes : require   (the library marks its loops [[unroll]])
//   Every public name starts with oas_, Oas or OAS_. It is plain GLSL 4.50 integer code: no 64-bit
//   types, no float division.
//   Every loop in the library runs a fixed, compile-time number of times and is marked
//   [[unroll]] (OAS_UNROLL), so the compiler turns it into straight-line code: the library adds
//   no iterations to your shader's loops, whatever the pattern, and you may loop over a pixel's
//   samples in one invocation as you like. (Lavapipe silently ends an invocation's loops after
//   65535 iterations in all; tests/loop_free_test.cpp evaluates every construction, field kind,
//   offset and baseline 4096+ times per invocation on it.) A compiler without
//   GL_EXT_control_flow_attributes may #define OAS_UNROLL as nothing before the include; its own
//   unrolling then decides whether the loops stay.
//   The same files compile as C++ (host/oas/glsl_compat.hpp), so the CPU reference is this code.
//   Before including, define either OAS_SOBOL_DIRECTION(dim, bit) (the Sobol baseline reads its
//   direction numbers through it: oas::sobolDirections() on the host, in a buffer) or
//   OAS_NO_SOBOL (the shader never receives a Sobol pattern); with neither it is a compile error.
//   Targets without umulExtended may define OAS_MULHI(a, b), e.g. as oas_mulhi_portable
//   (oas_intdiv.glsl).
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
//   uint  oas_pass_seed(uint pixelSeed, uint pass)               seed of a pass of N samples
//   float oas_sample(OasPattern p, uint pixelSeed, uint index, uint dim)
//         Dimension `dim` of sample `index` of the pixel: a pure function, fixed work, in [0, 1)
//         (never 1.0, never NaN, unless the shader's specialization does not fit p: see
//         ADVICE), exactly inside the strata the construction promises.
//   bool  oas_specialization_matches(OasPattern p)
//         false when the shader's OAS_STATIC_* do not fit p: then every value above is NaN.
//   const uint OAS_DRAW_MAX = 8u;   struct OasDraw { float u[OAS_DRAW_MAX]; };
//   OasDraw oas_draw(OasPattern p, uint pixelSeed, uint index, uint firstDim, uint dimCount)
//         Dimensions [firstDim, firstDim + dimCount) of sample `index` at once (dimCount <=
//         OAS_DRAW_MAX; u[k] = 0 beyond), each bit for bit oas_sample: one row state per
//         OA block the group touches, shared by its dimensions in that block (oas_draw.glsl). Every
//         construction and baseline; the call for a renderer's groups (camera ray, path vertex).
//         An includer whose draws span at most R blocks may define OAS_STATIC_DRAW_BLOCKS R for
//         speed (R rows a draw; NaN in every value of a draw that spans more: oas_draw.glsl).
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
//   OA constructions only (construction < OAS_RANDOM); baselines go through oas_sample, except:
//   bool          oas_is_padded_2d(OasPattern p)          jittered2d, cmj2d or zerotwo
//   OasPairColumn oas_pair_column(OasPattern p, uint passSeed, uint dim)
//   float         oas_pair_column_dim(OasPattern p, OasPairColumn c, uint index)
//   uint          oas_pair_cell(OasPairColumn c, uint index)
//   float         oas_pair_cell_dim(OasPattern p, OasPairColumn c, uint cell, uint index)
//         the padded 2D baselines' (jittered2d, cmj2d, zerotwo) fast path: the pair's keys and
//         the grid's reciprocals once per (pixel, pass, dimension); index < N within the pass,
//         passSeed = oas_pass_seed(pixelSeed, pass).
//         The two dimensions of a pair share one cell (oas_pair_cell) per sample.
//   A progressive sequence (oas_faure.glsl): the sampler OAS_FAURE (oas_sample and oas_draw take
//   it as any other pattern), and its parts for a renderer that makes its own sequences.
//   OasFaure oas_faure_make(OasField f, uint digits)        base q = f.q, indices below q^digits
//   uint     oas_faure_key(uint pixelSeed, uint block, uint element)
//   float    oas_faure_value(OasFaure fa, uint element, uint index, uint key)
//         The generalized Faure (0,s)-sequence in base q, nested-scrambled: dimension `element`
//         (< q, one field element per dimension, s <= q) of sample `index`. Every aligned block
//         of q^m consecutive samples is a (0,m,s)-net, so any prefix of lambda q^t samples is an
//         OA of strength t; its leading digit is Bush's OA. A shader whose sequences all have K
//         digits defines OAS_STATIC_FAURE_DIGITS to K for speed (every value NaN for another K);
//         one specialized on a faure OasPattern has K already (OAS_STATIC_INDEX_BITS).
//
// EXAMPLE (one invocation per pixel, looping over all of its samples; the library adds no loop
// iterations, so the loops may be as long as the renderer's own budget allows)
//   #extension GL_GOOGLE_include_directive : require
//   #extension GL_EXT_control_flow_attributes : require
//   #define OAS_NO_SOBOL
//   #include "oas/oas.glsl"
//   layout(push_constant) uniform Params { OasPattern pattern; uint frameSeed; uint spp; } params;
//   ...
//   uint seed = oas_pixel_seed(x, y, params.frameSeed);
//   for (uint first = 0u; first < params.spp; first += params.pattern.N) {   // passes of N
//       OasBlock b = oas_block(params.pattern, seed, first, 0u);            // dims 0, 1: block 0
//       OasColumn c0 = oas_column(params.pattern, b.seed, 0u);
//       OasColumn c1 = oas_column(params.pattern, b.seed, 1u);
//       for (uint s = first; s < min(params.spp, first + params.pattern.N); ++s) {
//           OasRow row = oas_block_row(b, s);
//           vec2 pixelJitter = vec2(oas_column_dim(params.pattern, c0, row), oas_column_dim(params.pattern, c1, row));
//           ...
//       }
//   }
//   The one-shot oas_sample(params.pattern, seed, s, dim) gives the same values (and is the way
//   for baselines); oas_row + oas_row_dim share the row state across a block's dimensions.
//
// ADVICE
//   - Bose CMJ correlates the partner columns (0,1), (2,3), ...: each such pair is Kensler's
//     correlated multi-jitter, which converges like N^-1.5 on smooth integrands that differ
//     between opposite edges of the pair's square (N^-3 on periodic ones); MJ offsets give N^-2
//     on both (docs/STUDY.md). Prefer MJ for smooth, non-periodic pairs.
//   - Specialise the shader on the pattern kind (OAS_STATIC_CONSTRUCTION / _OFFSET / _FIELD_KIND /
//     _FIELD_DEGREE / _SMALL_N / _INDEX_BITS, e.g. from specialization constants, see oas_pattern.glsl) for
//     speed: lavapipe runs both sides of every branch, so an unspecialised shader pays for every
//     construction's code, for field loops as long as the largest field's, and for the stratum
//     point's long division. oas_specialization (oas_pattern.h) fills the six values for a
//     pattern. A specialized shader handed a pattern of another kind returns NaN in every value,
//     never wrong numbers (oas_specialized_value); oas_specialization_matches(p) says which.
//   - Fixed work. Each loop's trip count is the largest case the numeric contract allows: 12 bits
//     of a GF(2^k) element, 5 digits of an odd extension field's element, t <= 8 Bush digits, 12
//     exponent bits of an inverse, 5 exponent bits of CMJND's digit place, 24 bits of a (0,2)
//     index, 24 Halton digits (15 for any base, 9 more for base 2; the bits of N - 1 in a shader
//     specialized with OAS_STATIC_INDEX_BITS), 32 bits of a Sobol index.
//     Steps past the pattern's own k, t or digit count are masked. A value therefore costs the
//     same for every pattern of a kind, and lanes stay in lock step.
//   - Fetch the dimensions you need at one call site, not at every use: one oas_draw per group
//     of dimensions, in a loop over the groups (shaders/pt/pt_sample_dims.glsl calls it once, for
//     the camera and every path vertex). GPU compilers inline the whole sampler wherever it is
//     called: a path tracer that calls it at every use takes 20 s to build its pipeline on
//     lavapipe, against 1.5 s with one call site.
//   - A renderer that draws where it uses (oas_sample, oas_draw per path vertex) makes an OA
//     block's and column's state again for every value. Prefetch instead: define
//     OAS_PREFETCH_STORE(at, v) before including this file, and a kernel of its own dispatched
//     before the tracer calls oas_prefetch(p, seed, dim, index, n, offset, stride) once per
//     (pixel, dimension) for the tracer's next n samples (oas_prefetch.glsl says more).
//
// NUMERIC CONTRACT
//   Outputs are F * 2^-24 with integer F in [0, 2^24). A point promised to stratum m of K strata
//   (K = s for the OA levels, K = N for the MJ/CMJ Latin-hypercube property) satisfies
//   m/K <= x < (m+1)/K exactly, for K <= 2^24. All arithmetic is 32-bit unsigned and overflow-free
//   for the ranges the host accepts: N <= 2^24, so fields q <= 4096 (every OA has N >= q^2; odd
//   extension fields only where oas_gf_slots_fit, which leaves out GF(3^6), GF(3^7), GF(5^5) and
//   GF(7^4)), any 32-bit seed, pixel coordinate, dimension or sample index (index >= N starts a
//   new randomized pass).
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

#ifndef OAS_UNROLL
#define OAS_UNROLL [[unroll]]
#endif

#include "oas_hash.glsl"
#include "oas_intdiv.glsl"
#include "oas_permute.glsl"
#include "oas_strata.glsl"
#include "oas_gf.glsl"
#include "oas_pattern.glsl"
#include "oas_oa.glsl"
#include "oas_faure.glsl"
#include "oas_baselines.glsl"

/// oas_sample for the baseline samplers alone (construction >= OAS_RANDOM): a caller that handles
/// the OA constructions through the fast path calls this for the rest, so the OA code is compiled
/// into its shader once, not twice.
float oas_baseline_sample(OasPattern pat, uint pixelSeed, uint index, uint dim)
{
    uint pass = oas_div_n(pat, index);
    return oas_baseline_dim(pat, oas_pass_seed(pixelSeed, pass), index - pass * pat.N, dim);
}

/// Dimension `dim` of sample `index` for the pixel with seed `pixelSeed`. See the API above.
float oas_sample(OasPattern pat, uint pixelSeed, uint index, uint dim)
{
    if (OAS_CONSTRUCTION(pat) >= OAS_RANDOM) return oas_baseline_sample(pat, pixelSeed, index, dim);
    uint block = dim / pat.blockDims;
    OasRow r = oas_row(pat, pixelSeed, index, block);
    return oas_row_dim(pat, r, dim - block * pat.blockDims);
}

#include "oas_draw.glsl"
#ifdef OAS_PREFETCH_STORE
#include "oas_prefetch.glsl"
#endif

#endif // OAS_GLSL
