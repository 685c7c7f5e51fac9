#pragma once
// The compiled variants of OaColumns (oa_columns.hpp): one per construction and field kind the
// pattern builder makes (host/oas/oas_pattern.c), as X(name, construction, field kind). The build
// reads this list too (host/oas/CMakeLists.txt) and compiles oa_columns_variant.inc once per entry,
// plus the generic variant. Keep one entry per line, in this form.
#define OAS_OA_COLUMN_VARIANTS(X)                                                                                                \
    X(bose_prime, OAS_BOSE, OAS_FIELD_PRIME)                                                                                     \
    X(bose_binary, OAS_BOSE, OAS_FIELD_BINARY)                                                                                   \
    X(bose_odd, OAS_BOSE, OAS_FIELD_ODD_EXTENSION)                                                                               \
    X(bush_prime, OAS_BUSH, OAS_FIELD_PRIME)                                                                                     \
    X(bush_binary, OAS_BUSH, OAS_FIELD_BINARY)                                                                                   \
    X(bush_odd, OAS_BUSH, OAS_FIELD_ODD_EXTENSION)                                                                               \
    X(bose_bush_binary, OAS_BOSE_BUSH, OAS_FIELD_BINARY)                                                                         \
    X(ak_prime, OAS_ADDELMAN_KEMPTHORNE, OAS_FIELD_PRIME)                                                                        \
    X(ak_odd, OAS_ADDELMAN_KEMPTHORNE, OAS_FIELD_ODD_EXTENSION)                                                                  \
    X(cmjnd, OAS_CMJND, OAS_FIELD_PRIME)

// Binary-field variants that also fix the field's degree k (OAS_STATIC_FIELD_DEGREE), as
// D(name, construction, k): the multiply then runs k steps instead of all twelve, which made
// Bose over GF(2^3) with CMJ offsets 1.19-1.24x faster on the CPU and Bose-Bush over GF(2^4)
// 1.15x (oas-bench, 2-vCPU AMD EPYC, AVX2). They are built for the CMJ offset only, the
// renderer's default, and for GF(4) to GF(32): Bose with 16 to 1024 samples per pass, Bose-Bush
// with 8 to 512. Every other binary pattern takes its variant above. Each is a compile of about
// 5 s, which is why there are not more.
#define OAS_OA_COLUMN_DEGREE_VARIANTS(D)                                                                                         \
    D(bose_binary, OAS_BOSE, 2)                                                                                                  \
    D(bose_binary, OAS_BOSE, 3)                                                                                                  \
    D(bose_binary, OAS_BOSE, 4)                                                                                                  \
    D(bose_binary, OAS_BOSE, 5)                                                                                                  \
    D(bose_bush_binary, OAS_BOSE_BUSH, 2)                                                                                        \
    D(bose_bush_binary, OAS_BOSE_BUSH, 3)                                                                                        \
    D(bose_bush_binary, OAS_BOSE_BUSH, 4)                                                                                        \
    D(bose_bush_binary, OAS_BOSE_BUSH, 5)
