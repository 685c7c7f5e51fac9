#version 450
// "Another renderer" embedding the oas GLSL library: it already has its own hashing and RNG under
// the short, common names that libraries tend to pick (hash, permute, random, rand, pcg, hash2,
// fastdiv, mulhi), its own structs Pattern, Field and Row, and constants ONE and N. All of them are
// declared before the include, with signatures a careless library would also use, so any
// unprefixed name in shaders/oas/*.glsl turns into a redefinition error here. The shader writes
// oas_sample() values next to its own hash() values. Compiled by tests/embedding_test.cpp:
//   glslangValidator --target-env vulkan1.1 -I<repo>/shaders other_renderer.comp
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

layout(local_size_x = 64) in;

// ---- the renderer's own names ----------------------------------------------------------------
const uint ONE = 1u;
const uint N = 16u;  // the renderer's sample count (the library's OasPattern.N is a member, not this)

struct Pattern {
    uint kind;
    uint count;
};

struct Field {
    vec3 value;
    float weight;
};

struct Row {
    uint index;
    float u;
};

uint mulhi(uint a, uint b)
{
    uint hi;
    uint lo;
    umulExtended(a, b, hi, lo);
    return hi;
}

uint fastdiv(uint x, uint recip, uint l) { return (mulhi(x, recip) >> l) + ONE - ONE; }

uint pcg(uint v)
{
    uint state = v * 1664525u + 1013904223u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

uint hash(uint x)
{
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

uint hash2(uint a, uint b) { return hash(a ^ pcg(b)); }

uint permute(uint i, uint l, uint seed) { return (i + hash(seed)) % l; }

float random(uint seed) { return float(hash(seed) >> 8u) * (1.0 / 16777216.0); }

float rand(inout uint state)
{
    state = pcg(state);
    return float(state >> 8u) * (1.0 / 16777216.0);
}

Pattern renderPattern;  // a renderer global of its own struct type
uint rngState;

// ---- the library ---------------------------------------------------------------------------
#define OAS_NO_SOBOL  // this shader never gets a Sobol pattern
#include "oas/oas.glsl"

// ---- the renderer's interface ----------------------------------------------------------------
layout(push_constant) uniform Params {
    OasPattern pattern;  // made on the host by oas::makePattern, uploaded as is (16 uints)
    uint frameSeed;
    uint spp;
    uint dims;
} params;

layout(std430, binding = 0) writeonly buffer Samples { float samples[]; };
layout(std430, binding = 1) writeonly buffer Hashes { uint hashes[]; };

void main()
{
    uint item = gl_GlobalInvocationID.x;
    if (item >= params.spp * params.dims) return;
    uint index = item / params.dims;
    uint dim = item - index * params.dims;

    // The library's sampler, both entry points.
    uint seed = oas_pixel_seed(gl_WorkGroupID.y, gl_WorkGroupID.z, params.frameSeed);
    float value = oas_sample(params.pattern, seed, index, dim);
    if (params.pattern.construction < OAS_RANDOM) {
        uint block = dim / params.pattern.blockDims;
        OasRow oasRow = oas_row(params.pattern, seed, index, block);
        value = oas_row_dim(params.pattern, oasRow, dim - block * params.pattern.blockDims);
    }
    samples[item] = value;

    // The renderer's own functions and types, used side by side with the library's.
    renderPattern.kind = params.pattern.construction;
    renderPattern.count = N;
    rngState = hash2(item, params.frameSeed);
    Row row;
    row.index = permute(item, renderPattern.count, rngState);
    row.u = rand(rngState) + random(item);
    Field field;
    field.value = vec3(row.u, value, 0.0);
    field.weight = float(ONE);
    uint mixed = fastdiv(pcg(row.index), 0x80000001u, 1u) ^ mulhi(item, 0x9e3779b9u);
    hashes[item] = hash(item) ^ (uint(field.weight) - ONE) ^ (mixed & 0u);
}
