#pragma once
// The GLSL library's field descriptor (OasField, shaders/oas/oas_gf.glsl) for GF(p^k), filled as
// the host fills a pattern's: the library's reduction polynomial and oas_fastdiv constants of p.
// For tests that call the field arithmetic, or what is built on it, directly.
#include <cstdint>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "test_cases.hpp"

namespace oas::test {

inline oas::glsl::OasField libraryField(std::uint32_t p, std::uint32_t k)
{
    oas::glsl::OasField f;
    f.p = p;
    f.k = k;
    f.q = ipow(p, k);
    f.poly = oas::primitivePolynomial(p, k);
    const oas::Divisor byP = oas::makeDivisor(p);
    f.recipP = byP.recip;
    f.shiftP = byP.shift;
    return f;
}

}  // namespace oas::test
