#pragma once
// The compiled variants of OaColumns (oa_columns.hpp): one per construction and field kind the
// pattern builder makes (host/oas/oas_pattern.c), as X(name, construction, field kind). The build
// reads this list too (host/oas/CMakeLists.txt) and compiles oa_columns_variant.inc once per entry,
// plus the generic variant. Keep one entry per line, in this form.
#define OAS_OA_COLUMN_VARIANTS(X)                               \
    X(bose_prime, OAS_BOSE, OAS_FIELD_PRIME)                    \
    X(bose_binary, OAS_BOSE, OAS_FIELD_BINARY)                  \
    X(bose_odd, OAS_BOSE, OAS_FIELD_ODD_EXTENSION)              \
    X(bush_prime, OAS_BUSH, OAS_FIELD_PRIME)                    \
    X(bush_binary, OAS_BUSH, OAS_FIELD_BINARY)                  \
    X(bush_odd, OAS_BUSH, OAS_FIELD_ODD_EXTENSION)              \
    X(bose_bush_binary, OAS_BOSE_BUSH, OAS_FIELD_BINARY)        \
    X(ak_prime, OAS_ADDELMAN_KEMPTHORNE, OAS_FIELD_PRIME)       \
    X(ak_odd, OAS_ADDELMAN_KEMPTHORNE, OAS_FIELD_ODD_EXTENSION) \
    X(cmjnd, OAS_CMJND, OAS_FIELD_PRIME)
