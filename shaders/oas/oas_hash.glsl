// oas_hash.glsl - stateless hashing of 32-bit words: the library's source of seeds and keys.
// Part of the oas GLSL library; include "oas.glsl" rather than this file. Depends on nothing.
// Shared verbatim with C++ through host/oas/glsl_compat.hpp: keep to the GLSL/C++ common subset
// (scalar uint/float, structs built member by member, no in/out/inout qualifiers).
#ifndef OAS_HASH_GLSL
#define OAS_HASH_GLSL

/// 32-bit integer hash: the PCG-based hash recommended by Jarzynski and Olano,
/// "Hash Functions for GPU Rendering" (JCGT 2020). A bijection on 32 bits.
uint oas_pcg(uint v)
{
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/// Hash of two words; order matters (oas_hash2(a, b) != oas_hash2(b, a) in general).
uint oas_hash2(uint a, uint b) { return oas_pcg(a ^ oas_pcg(b + 0x9e3779b9u)); }

/// Hash of three words.
uint oas_hash3(uint a, uint b, uint c) { return oas_hash2(oas_hash2(a, b), c); }

#endif // OAS_HASH_GLSL
