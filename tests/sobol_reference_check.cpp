// sobol_reference_check - the unscrambled Sobol points of the shared GLSL code, for
// tests/sobol_scipy_test.py to compare with scipy.stats.qmc.Sobol.
//
//   sobol_reference_check DIMS < indices
//
// reads whitespace-separated point indices (decimal) from stdin and writes, for each in order,
// DIMS words: oas_sobol(index, dim) for dim = 0 .. DIMS-1, as 32-bit little-endian integers on
// stdout. oas_sobol is shaders/oas/oas_baselines.glsl compiled as C++ (oas/glsl_compat.hpp) with
// the host's direction numbers, so what is checked is exactly what every shader computes before
// Owen scrambling. Which indices to ask for (scipy's points come in Gray-code order) is the
// driver's business: this program knows nothing of scipy.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "oas/glsl_compat.hpp"

int main(int argc, char** argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s DIMS < indices\n", argv[0]);
        return 2;
    }
    char* end = nullptr;
    const unsigned long dims = std::strtoul(argv[1], &end, 10);
    // Dimensions past one block would read past the direction-number table.
    if (*end != '\0' || dims < 1 || dims > oas::glsl::OAS_SOBOL_BLOCK) {
        std::fprintf(stderr, "DIMS must be 1 .. %u, got %s\n", unsigned(oas::glsl::OAS_SOBOL_BLOCK), argv[1]);
        return 2;
    }
    std::vector<unsigned char> row(dims * 4);
    std::string token;
    while (std::cin >> token) {
        const unsigned long long index = std::strtoull(token.c_str(), &end, 10);
        if (*end != '\0' || index > 0xffffffffull) {
            std::fprintf(stderr, "bad index %s (want 0 .. 2^32-1)\n", token.c_str());
            return 2;
        }
        for (std::uint32_t d = 0; d < dims; ++d) {
            const std::uint32_t x = oas::glsl::oas_sobol(std::uint32_t(index), d);
            for (int b = 0; b < 4; ++b) row[d * 4 + b] = static_cast<unsigned char>(x >> (8 * b));
        }
        if (std::fwrite(row.data(), 1, row.size(), stdout) != row.size()) return 3;
    }
    return std::fflush(stdout) == 0 ? 0 : 3;
}
