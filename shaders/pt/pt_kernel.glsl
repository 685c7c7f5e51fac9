// pt_kernel.glsl - what the GPU path-tracing kernels share: the specialization constants, the
// oas library specialised by them, the scene's texel buffers and their accessors, the prefetched
// samples and the exact per-pixel sums. pt_render.comp (the megakernel: a whole path per
// invocation) and pt_wavefront.comp (the path as data: one step per dispatch) include it first,
// then declare their push constants (whose first member is the OasPattern) and pt_pattern(), then
// include pt/pt_trace.glsl. Not shared with the C++ twin (it is the GPU side's binding layer).
#ifndef PT_KERNEL_GLSL
#define PT_KERNEL_GLSL

// Every specialization constant and buffer binding comes from one table, pt/pt_constants.glsl
// (the host fills the same table: host/render/tracer_gpu.cpp).
#include "pt/pt_constants.glsl"
#define PT_DECLARE_SPEC_CONSTANT(NAME, ID, TYPE, DEFAULT, HOST) layout(constant_id = ID) const TYPE NAME = DEFAULT;
PT_SAMPLER_CONSTANTS(PT_DECLARE_SPEC_CONSTANT)
#define OAS_STATIC_CONSTRUCTION oasSpecConstruction
#define OAS_STATIC_OFFSET oasSpecOffset
#define OAS_STATIC_FIELD_KIND oasSpecFieldKind
#define OAS_STATIC_FIELD_DEGREE oasSpecFieldDegree
#define OAS_STATIC_SMALL_N oasSpecSmallN
#define OAS_STATIC_INDEX_BITS oasSpecIndexBits
// The Sobol baselines' direction numbers (oas::sobolDirections(), 1024 dims x 32 bits), as texels
// of four: lavapipe fetches a texel for all lanes at once, where it loaded a storage-buffer
// element one lane at a time. `bit` is a constant in the library's unrolled loop, so the
// component is too, and the four fetches of one texel are one.
layout(binding = PT_BINDING_SOBOL_DIRECTIONS) uniform usamplerBuffer sobolTexels;
#define OAS_SOBOL_DIRECTION(dim, bit) texelFetch(sobolTexels, int((dim) * 8u + (bit) / 4u))[(bit) & 3u]
#include "oas/oas.glsl"

PT_PLAN_CONSTANTS(PT_DECLARE_SPEC_CONSTANT)
PT_KERNEL_CONSTANTS(PT_DECLARE_SPEC_CONSTANT)
// The scene's features as specialization constants (pt/pt_trace.glsl otherwise keeps every path).
#define PT_SCENE_FEATURES
PT_SCENE_FEATURE_CONSTANTS(PT_DECLARE_SPEC_CONSTANT)

#include "pt/pt_types.glsl"
#include "pt/pt_accumulate.glsl"

// The scene data as texel buffers of uvec4, each record its vec4 fields in order (the C++
// layout of pt_types.glsl): lavapipe fetches texels for all its lanes at once, while it ran a
// storage-buffer load one lane at a time, even for the globals every lane reads alike
// (pt_constants.glsl's PT_BINDINGS).
layout(binding = PT_BINDING_SHAPES) uniform usamplerBuffer shapeTexels;
layout(binding = PT_BINDING_MATERIALS) uniform usamplerBuffer materialTexels;
layout(binding = PT_BINDING_LIGHTS) uniform usamplerBuffer lightTexels;
layout(binding = PT_BINDING_NODES) uniform usamplerBuffer nodeTexels;
layout(binding = PT_BINDING_GLOBALS) uniform usamplerBuffer globalTexels;
// Exact per-pixel sums, PT_SUM_WORDS words per pixel (pt/pt_accumulate.glsl).
layout(std430, binding = PT_BINDING_ACCUMULATION) buffer Accumulation { uint accumulation[]; };

/// Field k of record i, records of n vec4s.
#define PT_TEXEL(texels, i, n, k) uintBitsToFloat(texelFetch(texels, int((i) * (n) + (k))))
PtShape pt_shape(uint i)
{
    return PtShape(PT_TEXEL(shapeTexels, i, 5u, 0u), PT_TEXEL(shapeTexels, i, 5u, 1u), PT_TEXEL(shapeTexels, i, 5u, 2u),
                   PT_TEXEL(shapeTexels, i, 5u, 3u), PT_TEXEL(shapeTexels, i, 5u, 4u));
}
PtMaterial pt_material(uint i)
{
    return PtMaterial(PT_TEXEL(materialTexels, i, 3u, 0u), PT_TEXEL(materialTexels, i, 3u, 1u),
                      PT_TEXEL(materialTexels, i, 3u, 2u));
}
PtLight pt_light(uint i)
{
    return PtLight(PT_TEXEL(lightTexels, i, 4u, 0u), PT_TEXEL(lightTexels, i, 4u, 1u), PT_TEXEL(lightTexels, i, 4u, 2u),
                   PT_TEXEL(lightTexels, i, 4u, 3u));
}
PtNode pt_node(uint i) { return PtNode(PT_TEXEL(nodeTexels, i, 2u, 0u), PT_TEXEL(nodeTexels, i, 2u, 1u)); }
PtGlobals pt_globals()
{
    return PtGlobals(PT_TEXEL(globalTexels, 0u, 7u, 0u), PT_TEXEL(globalTexels, 0u, 7u, 1u), PT_TEXEL(globalTexels, 0u, 7u, 2u),
                     PT_TEXEL(globalTexels, 0u, 7u, 3u), PT_TEXEL(globalTexels, 0u, 7u, 4u), PT_TEXEL(globalTexels, 0u, 7u, 5u),
                     PT_TEXEL(globalTexels, 0u, 7u, 6u));
}

// The batch's OA sample values, where PT_PREFETCH_DIMS != 0: the generation kernel
// (oas_generate.comp) wrote them in the dispatch before, [pixel of the tile][sample of the
// batch][dimension], PT_PREFETCH_DIMS (a multiple of 4) dimensions per sample. Made there, a
// pixel's block and column state (seeds, permutation keys) is shared by the batch's samples,
// where oas_draw in the tracer makes it again for every sample; on lavapipe that was ~40% of a 7D
// frame.
layout(binding = PT_BINDING_SAMPLES) uniform usamplerBuffer sampleTexels;

/// A group's values from the prefetched samples: dimensions [first, first + count) of the sample
/// whose values start at texel sampleTexel. `first` is shared by all lanes (the vertex loop runs
/// in step), so the three texels holding dimensions first .. first + 7 are read and each value
/// picked by the shared offset first % 4 (selects, not a private array: lavapipe reads those
/// through memory). Dimensions past the prefetched ones (the group after the last vertex, which
/// has count 0) read the sample's last texel instead.
OasDraw pt_prefetched_group(uint sampleTexel, uint first, uint count)
{
    uint lastTexel = PT_PREFETCH_DIMS / 4u - 1u;
    uint firstTexel = first / 4u;
    uint shift = first - firstTexel * 4u;
    uvec4 t0 = texelFetch(sampleTexels, int(sampleTexel + min(firstTexel, lastTexel)));
    uvec4 t1 = texelFetch(sampleTexels, int(sampleTexel + min(firstTexel + 1u, lastTexel)));
    uvec4 t2 = texelFetch(sampleTexels, int(sampleTexel + min(firstTexel + 2u, lastTexel)));
    uint w[12] = uint[12](t0.x, t0.y, t0.z, t0.w, t1.x, t1.y, t1.z, t1.w, t2.x, t2.y, t2.z, t2.w);
    OasDraw d;
    [[unroll]] for (uint k = 0u; k < OAS_DRAW_MAX; ++k) {
        uint bits = shift == 0u ? w[k] : (shift == 1u ? w[k + 1u] : (shift == 2u ? w[k + 2u] : w[k + 3u]));
        d.u[k] = k < count ? uintBitsToFloat(bits) : 0.0f;
    }
    return d;
}

/// Adds one dispatch's samples of pixel (px, py) to its exact sums: `sum` of the summable ones,
/// `samples` taken, `rejected` of them left out. Every pixel has one invocation per dispatch, so
/// a plain read-modify-write, no atomics.
void pt_add_to_pixel(uint px, uint py, PtSum sum, uint samples, uint rejected)
{
    uint base = (py * uint(pt_globals().image.x) + px) * PT_SUM_WORDS;
    PtSum before;
    before.lo = uvec3(accumulation[base], accumulation[base + 3u], accumulation[base + 6u]);
    before.mid = uvec3(accumulation[base + 1u], accumulation[base + 4u], accumulation[base + 7u]);
    before.hi = uvec3(accumulation[base + 2u], accumulation[base + 5u], accumulation[base + 8u]);
    PtSum after = pt_sum_add(before, sum);
    [[unroll]] for (uint c = 0u; c < 3u; ++c) {
        accumulation[base + 3u * c] = after.lo[c];
        accumulation[base + 3u * c + 1u] = after.mid[c];
        accumulation[base + 3u * c + 2u] = after.hi[c];
    }
    accumulation[base + PT_SUM_COUNT_WORD] += samples;
    accumulation[base + PT_SUM_REJECTED_WORD] += rejected;
}

#endif // PT_KERNEL_GLSL
