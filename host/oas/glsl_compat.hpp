#pragma once
// Compiles the GLSL sampler library (shaders/oas/*.glsl) as C++: the CPU twin *is* the shader
// source, so the two cannot drift (the approach of nvpro-samples' shared headers and pbrt-v4's
// host/device code). The library keeps to the common subset of GLSL and C++: scalar uint/float,
// structs filled member by member, builtins provided here with GLSL's exact semantics.
//
// Everything lands in an anonymous namespace: each translation unit gets private copies of the
// (non-inline) GLSL functions, so any file may include this header without ODR clashes. Host APIs
// therefore pass oas::Pattern (host/oas/pattern.hpp) and convert with oas::glsl::toGlsl().
#include <bit>
#include <cstdint>
#include <cstring>

#include "oas/pattern.hpp"

namespace oas {
/// sobolDirections().data(), kept in an inline function's static: an inlined guard test per
/// direction number, where a call to sobolDirections() per number was 7% of the CPU's Sobol
/// values in perf (docs/BENCHMARKS.md).
inline const std::uint32_t* sobolDirectionData()
{
    static const std::uint32_t* const data = sobolDirections().data();
    return data;
}
}  // namespace oas

namespace oas::glsl {
namespace {

using uint = std::uint32_t;

/// GLSL umulExtended: the 64-bit product of two uints, split into high and low words.
inline void umulExtended(uint x, uint y, uint& msb, uint& lsb)
{
    const std::uint64_t product = std::uint64_t(x) * std::uint64_t(y);
    msb = uint(product >> 32);
    lsb = uint(product);
}

/// GLSL bitCount: the number of set bits.
inline int bitCount(uint v)
{
    return std::popcount(v);
}

/// GLSL findMSB: index of the highest set bit, -1 for 0.
inline int findMSB(uint v)
{
    return v == 0 ? -1 : 31 - std::countl_zero(v);
}

/// GLSL bitfieldReverse: bit b of the result is bit 31 - b of v (swap halves, then bytes, nibbles,
/// pairs and bits).
inline uint bitfieldReverse(uint v)
{
    v = ((v >> 1u) & 0x55555555u) | ((v & 0x55555555u) << 1u);
    v = ((v >> 2u) & 0x33333333u) | ((v & 0x33333333u) << 2u);
    v = ((v >> 4u) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4u);
    v = ((v >> 8u) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8u);
    return (v >> 16u) | (v << 16u);
}

/// GLSL uintBitsToFloat: the float with these bits.
inline float uintBitsToFloat(uint v)
{
    return std::bit_cast<float>(v);
}

/// GLSL min for uints.
inline uint min(uint a, uint b)
{
    return a < b ? a : b;
}

// The library's [[unroll]] marks (GL_EXT_control_flow_attributes) mean nothing to C++ by default.
// Code that g++ vectorizes defines OAS_UNROLL as its unroll pragma first (oa_columns_variant.inc):
// left as loops, the field loops stop the vectorizer; everywhere, the pragma made the flattened
// scalar generator (generate_cpu.cpp) take 160 s to compile instead of seconds.
#ifndef OAS_UNROLL
#define OAS_UNROLL
#endif

// On a CPU a branch skips work where a GPU would predicate it: the field loops skip the steps
// past the field's degree (oas_gf.glsl), and the stratum point divides once where K <= 2^16
// (oas_strata.glsl). A shader gets the same by specialisation (OAS_STATIC_*); the values are the
// same either way.
// Code that g++ vectorizes across samples wants the GPU's form instead, where every lane does the
// same steps (host/oas/oa_columns_variant.inc): it defines OAS_NO_RUNTIME_BRANCHES first.
#ifndef OAS_NO_RUNTIME_BRANCHES
#define OAS_RUNTIME_BRANCHES
#endif

// The C++ twin has the Sobol baseline: its direction numbers come from the host's table
// (sobolDirectionData, above).
#define OAS_SOBOL_DIRECTION(dim, bit) (::oas::sobolDirectionData()[(dim)*32u + (bit)])

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wunused-variable"
#include "oas/oas.glsl"
#pragma GCC diagnostic pop

static_assert(sizeof(OasPattern) == 16 * sizeof(uint), "OasPattern must stay 16 uints");
static_assert(sizeof(OasPattern) == sizeof(oas::Pattern), "oas::Pattern mirrors OasPattern");

/// The host's oas::Pattern as this translation unit's OasPattern (the same 16 uints).
inline OasPattern toGlsl(const oas::Pattern& p)
{
    OasPattern g;
    std::memcpy(&g, &p, sizeof(g));
    return g;
}

}  // namespace
}  // namespace oas::glsl
