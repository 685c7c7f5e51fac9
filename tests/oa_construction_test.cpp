// The un-randomized orthogonal arrays of the GLSL library (oas_oa_level / oas_oa_sublevel in
// shaders/oas/oas_oa.glsl, compiled as C++) against independent textbook constructions
// (textbook_oa.hpp): entry-for-entry equality, the orthogonal-array property checked
// exhaustively, the sub-level bijections the MJ/CMJ offsets rely on, and parameter validation.
//
// Runtime: every strength check below is exhaustive over ALL t-subsets of columns; the largest
// cases (Bose q = 64: 2080 column pairs x 4096 rows; Bose-Bush q = 32: 2080 pairs x 2048 rows;
// Bush q = 16, t = 3: 680 triples x 4096 rows) take milliseconds, so nothing is subsampled.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "test_cases.hpp"
#include "textbook_oa.hpp"

namespace {

struct OaCase {
    std::string sampler;
    std::uint32_t q;  ///< levels s (CMJND: s)
    std::uint32_t t;  ///< strength (CMJND: d)
};

void PrintTo(const OaCase& c, std::ostream* os)
{
    *os << c.sampler << " q=" << c.q << " t=" << c.t;
}

using oas::test::ipow;

std::vector<OaCase> oaCases()
{
    std::vector<OaCase> cases;
    for (std::uint32_t q : {2u, 3u, 4u, 5u, 7u, 8u, 9u, 11u, 13u, 16u, 25u, 27u, 32u, 49u, 64u}) cases.push_back({"bose", q, 2});
    for (auto [q, t] : std::vector<std::pair<std::uint32_t, std::uint32_t>>{
             {2, 2}, {3, 3}, {4, 3}, {4, 4}, {5, 3}, {5, 4}, {7, 3}, {8, 3}, {9, 3}, {8, 4}, {16, 3}})
        cases.push_back({"bush", q, t});
    for (std::uint32_t q : {2u, 4u, 8u, 16u, 32u}) cases.push_back({"bose-bush", q, 2});
    for (std::uint32_t q : {3u, 5u, 7u, 9u, 11u, 13u, 25u, 27u}) cases.push_back({"addelman-kempthorne", q, 2});
    for (auto [s, d] :
         std::vector<std::pair<std::uint32_t, std::uint32_t>>{{2, 2}, {2, 3}, {2, 5}, {3, 3}, {3, 4}, {5, 3}, {4, 4}, {2, 10}})
        cases.push_back({"cmjnd", s, d});
    return cases;
}

std::string caseName(const testing::TestParamInfo<OaCase>& info)
{
    std::string name;
    for (char c : info.param.sampler) name += c == '-' ? '_' : c;
    return name + "_q" + std::to_string(info.param.q) + "_t" + std::to_string(info.param.t);
}

/// Rows N, columns c of the construction.
std::uint32_t expectedN(const OaCase& c)
{
    if (c.sampler == "bose") return c.q * c.q;
    if (c.sampler == "bush" || c.sampler == "cmjnd") return ipow(c.q, c.t);
    return 2 * c.q * c.q;
}
std::uint32_t expectedColumns(const OaCase& c)
{
    if (c.sampler == "bose" || c.sampler == "bush") return c.q + 1;
    if (c.sampler == "cmjnd") return c.t;
    return 2 * c.q + 1;
}

oas::Pattern makeFor(const OaCase& c)
{
    oas::PatternRequest r;
    r.sampler = c.sampler;
    r.spp = expectedN(c);
    r.dims = expectedColumns(c);
    r.offset = "cmj";
    // Bush needs its strength; the others take their default (2; CMJND: dims).
    r.strength = c.sampler == "bush" ? c.t : 0;
    return oas::makePattern(r);
}

oas::glsl::OasPattern toGlsl(const oas::Pattern& p)
{
    oas::glsl::OasPattern g;
    static_assert(sizeof(g) == sizeof(p));
    std::memcpy(&g, &p, sizeof(g));
    return g;
}

/// The library's un-randomized array, N x blockDims, from oas_oa_level.
textbook::Array libraryArray(const oas::glsl::OasPattern& pat)
{
    textbook::Array A(pat.N, std::vector<int>(pat.blockDims));
    for (std::uint32_t r = 0; r < pat.N; ++r)
        for (std::uint32_t c = 0; c < pat.blockDims; ++c) A[r][c] = int(oas::glsl::oas_oa_level(pat, r, c));
    return A;
}

/// The textbook field for the pattern's GF(p^k) and its reduction polynomial.
textbook::Field fieldOf(const oas::Pattern& pat)
{
    return textbook::Field(int(pat.fieldP), int(pat.fieldK), pat.fieldPoly);
}

textbook::Array textbookArray(const OaCase& c, const oas::Pattern& pat)
{
    if (c.sampler == "cmjnd") return textbook::fullFactorial(int(c.q), int(c.t));
    const textbook::Field F = fieldOf(pat);
    if (c.sampler == "bose") return textbook::bose(F);
    if (c.sampler == "bush") return textbook::bush(F, int(c.t));
    if (c.sampler == "bose-bush") return textbook::boseBush(F);
    return textbook::addelmanKempthorne(F, F.smallestNonSquare());
}

class OaConstructionTest : public testing::TestWithParam<OaCase> {
protected:
    void SetUp() override
    {
        ASSERT_NO_THROW(pattern = makeFor(GetParam()));
        glslPattern = toGlsl(pattern);
    }
    oas::Pattern pattern;
    oas::glsl::OasPattern glslPattern{};
};

TEST_P(OaConstructionTest, PatternParameters)
{
    const OaCase& c = GetParam();
    EXPECT_EQ(pattern.N, expectedN(c));
    EXPECT_EQ(pattern.s, c.q);
    EXPECT_EQ(pattern.strength, c.t);
    EXPECT_EQ(pattern.blockDims, expectedColumns(c));
    if (c.sampler == "cmjnd") return;
    const std::uint32_t fieldQ = c.sampler == "bose-bush" ? 2 * c.q : c.q;
    const oas::PrimePower pk = oas::primePower(fieldQ);
    EXPECT_EQ(pattern.fieldP, pk.p);
    EXPECT_EQ(pattern.fieldK, pk.k);
    EXPECT_EQ(pattern.fieldQ, fieldQ);
    EXPECT_EQ(pattern.fieldPoly, pk.k > 1 ? oas::primitivePolynomial(pk.p, pk.k) : 0u);
    // The reduction polynomial must give a field (independent brute-force check).
    EXPECT_TRUE(textbook::isIrreducible(fieldOf(pattern).modulus(), int(pattern.fieldP)));
    if (c.sampler == "bush") {
        EXPECT_EQ(pattern.aux, ipow(c.q, c.t - 1));
    }
    if (c.sampler == "addelman-kempthorne") {
        const textbook::Field F = fieldOf(pattern);
        // aux must be a non-square of GF(q); the library takes the smallest.
        EXPECT_EQ(int(pattern.aux), F.smallestNonSquare());
        for (int a = 0; a < F.q(); ++a) EXPECT_NE(F.mul(a, a), int(pattern.aux)) << a;
    }
}

TEST_P(OaConstructionTest, LevelsMatchTextbook)
{
    const textbook::Array ref = textbookArray(GetParam(), pattern);
    const textbook::Array lib = libraryArray(glslPattern);
    ASSERT_EQ(ref.size(), lib.size());
    long long mismatches = 0;
    for (std::size_t r = 0; r < ref.size(); ++r) {
        ASSERT_EQ(ref[r].size(), lib[r].size());
        for (std::size_t c = 0; c < ref[r].size(); ++c)
            if (ref[r][c] != lib[r][c] && mismatches++ < 5)
                ADD_FAILURE() << "row " << r << " col " << c << ": library " << lib[r][c] << ", textbook " << ref[r][c];
    }
    EXPECT_EQ(mismatches, 0);
}

TEST_P(OaConstructionTest, TextbookArrayIsOrthogonalArray)
{
    const OaCase& c = GetParam();
    const textbook::Array ref = textbookArray(c, pattern);
    std::string why;
    EXPECT_TRUE(textbook::isOrthogonalArray(ref, int(c.q), int(c.t), textbook::allColumns(int(expectedColumns(c))), &why)) << why;
}

TEST_P(OaConstructionTest, LibraryArrayIsOrthogonalArray)
{
    const textbook::Array lib = libraryArray(glslPattern);
    std::string why;
    EXPECT_TRUE(textbook::isOrthogonalArray(lib, int(pattern.s), int(pattern.strength),
                                            textbook::allColumns(int(pattern.blockDims)), &why))
        << why;
    // Strength t implies every lower strength.
    for (std::uint32_t t = 1; t < pattern.strength; ++t)
        EXPECT_TRUE(textbook::isOrthogonalArray(lib, int(pattern.s), int(t), textbook::allColumns(int(pattern.blockDims)), &why))
            << "t = " << t << ": " << why;
}

TEST_P(OaConstructionTest, SublevelIsBijectionOnEachLevelSet)
{
    const std::uint32_t N = glslPattern.N, s = glslPattern.s, sub = N / s;
    ASSERT_EQ(sub * s, N);
    long long failures = 0;
    for (std::uint32_t col = 0; col < glslPattern.blockDims; ++col) {
        // seen[level * sub + sublevel]: each (level, sublevel) exactly once <=> a bijection from
        // every level set (which then has exactly N/s rows) onto [0, N/s).
        std::vector<int> seen(N, 0);
        for (std::uint32_t row = 0; row < N; ++row) {
            const std::uint32_t level = oas::glsl::oas_oa_level(glslPattern, row, col);
            const std::uint32_t sl = oas::glsl::oas_oa_sublevel(glslPattern, row, col);
            if (level >= s || sl >= sub) {
                if (failures++ < 5)
                    ADD_FAILURE() << "col " << col << " row " << row << ": level " << level << ", sublevel " << sl;
                continue;
            }
            if (++seen[level * sub + sl] > 1 && failures++ < 5)
                ADD_FAILURE() << "col " << col << ": (level " << level << ", sublevel " << sl << ") repeated";
        }
    }
    EXPECT_EQ(failures, 0);
}

TEST_P(OaConstructionTest, CorruptedArrayFails)
{
    const OaCase& c = GetParam();
    const int s = int(c.q), t = int(c.t), cols = int(expectedColumns(c));
    for (const textbook::Array& good : {textbookArray(c, pattern), libraryArray(glslPattern)}) {
        ASSERT_TRUE(textbook::isOrthogonalArray(good, s, t, textbook::allColumns(cols)));
        // One entry changed, in the first, a middle and the last row / column.
        const std::size_t n = good.size();
        for (auto [r, col] : std::vector<std::pair<std::size_t, int>>{{0, 0}, {n / 2, cols / 2}, {n - 1, cols - 1}}) {
            textbook::Array bad = good;
            bad[r][col] = (bad[r][col] + 1) % s;
            EXPECT_FALSE(textbook::isOrthogonalArray(bad, s, t, textbook::allColumns(cols)))
                << "changed row " << r << " col " << col;
        }
        // An out-of-range level fails as well.
        textbook::Array bad = good;
        bad[0][0] = s;
        EXPECT_FALSE(textbook::isOrthogonalArray(bad, s, t, textbook::allColumns(cols)));
    }
}

INSTANTIATE_TEST_SUITE_P(Constructions, OaConstructionTest, testing::ValuesIn(oaCases()), caseName);

// ---- The checker itself -------------------------------------------------------------------------

TEST(OaChecker, HandWrittenArrays)
{
    // OA(4, 3, 2, 2): the smallest orthogonal array of strength 2 (the Bose array for q = 2).
    const textbook::Array oa4 = {{0, 0, 0}, {0, 1, 1}, {1, 0, 1}, {1, 1, 0}};
    EXPECT_TRUE(textbook::isOrthogonalArray(oa4, 2, 2, {0, 1, 2}));
    EXPECT_TRUE(textbook::isOrthogonalArray(oa4, 2, 1, {0, 1, 2}));
    EXPECT_FALSE(textbook::isOrthogonalArray(oa4, 2, 3, {0, 1, 2}));  // 4 rows cannot cover 2^3 cells
    EXPECT_EQ(textbook::bose(textbook::Field(2, 1, 0)), oa4);
    // Right counts, wrong structure: a repeated column covers only the diagonal cells.
    const textbook::Array diag = {{0, 0}, {0, 0}, {1, 1}, {1, 1}};
    EXPECT_TRUE(textbook::isOrthogonalArray(diag, 2, 1, {0, 1}));
    EXPECT_FALSE(textbook::isOrthogonalArray(diag, 2, 2, {0, 1}));
    // Subsets: the checker looks only at the listed columns.
    const textbook::Array withDup = {{0, 0, 0, 0}, {0, 1, 1, 0}, {1, 0, 1, 1}, {1, 1, 0, 1}};
    EXPECT_TRUE(textbook::isOrthogonalArray(withDup, 2, 2, {0, 1, 2}));
    EXPECT_TRUE(textbook::isOrthogonalArray(withDup, 2, 2, {1, 2, 3}));
    EXPECT_FALSE(textbook::isOrthogonalArray(withDup, 2, 2, {0, 1, 2, 3}));
    // Full factorial 3^2: strength 2 over 2 columns.
    EXPECT_TRUE(textbook::isOrthogonalArray(textbook::fullFactorial(3, 2), 3, 2, {0, 1}));
}

TEST(OaChecker, BoseIsNotStrengthThree)
{
    for (std::uint32_t q : {2u, 3u, 4u, 5u, 7u, 8u, 9u}) {
        oas::PatternRequest r;
        r.sampler = "bose";
        r.spp = q * q;
        r.dims = q + 1;
        const oas::glsl::OasPattern pat = toGlsl(oas::makePattern(r));
        const textbook::Array lib = libraryArray(pat);
        const auto cols = textbook::allColumns(int(q + 1));
        EXPECT_TRUE(textbook::isOrthogonalArray(lib, int(q), 2, cols)) << q;
        EXPECT_FALSE(textbook::isOrthogonalArray(lib, int(q), 3, cols)) << q;
        // A duplicated column keeps every 1D count but breaks strength 2 (no divisibility excuse).
        textbook::Array dup = lib;
        for (auto& row : dup) row.push_back(row[0]);
        EXPECT_TRUE(textbook::isOrthogonalArray(dup, int(q), 1, textbook::allColumns(int(q + 2)))) << q;
        EXPECT_FALSE(textbook::isOrthogonalArray(dup, int(q), 2, textbook::allColumns(int(q + 2)))) << q;
    }
}

TEST(OaChecker, BoseBushMultiplicationTableIsDifferenceScheme)
{
    // D(2q, 2q, q): for any two columns, the differences (XOR) d_{i,a} - d_{i,b} over the rows
    // contain every element of GF(2)^m exactly twice (the property the development relies on).
    for (std::uint32_t q : {2u, 4u, 8u, 16u, 32u}) {
        const oas::PrimePower pk = oas::primePower(2 * q);
        const textbook::Field F(2, int(pk.k), oas::primitivePolynomial(2, pk.k));
        const textbook::Array D = textbook::boseBushDifferenceScheme(F);
        long long bad = 0;
        for (std::uint32_t a = 0; a < 2 * q; ++a)
            for (std::uint32_t b = a + 1; b < 2 * q; ++b) {
                std::vector<int> count(q, 0);
                for (std::uint32_t i = 0; i < 2 * q; ++i) ++count[D[i][a] ^ D[i][b]];
                for (int n : count) bad += n != 2;
            }
        EXPECT_EQ(bad, 0) << "q = " << q;
    }
}

// ---- Parameter validation -----------------------------------------------------------------------

oas::PatternRequest request(const std::string& sampler, std::uint32_t spp, std::uint32_t dims, std::uint32_t strength)
{
    oas::PatternRequest r;
    r.sampler = sampler;
    r.spp = spp;
    r.dims = dims;
    r.strength = strength;
    return r;
}

TEST(OaValidation, BoseNonPrimePowerNamesNeighbours)
{
    try {
        oas::makePattern(request("bose", 100, 11, 0));
        FAIL() << "bose spp 100 (q = 10) was accepted";
    } catch (const oas::InvalidArgument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("81"), std::string::npos) << msg;
        EXPECT_NE(msg.find("121"), std::string::npos) << msg;
    }
    // Rounding up is allowed on request and lands on the next valid count.
    oas::PatternRequest up = request("bose", 100, 11, 0);
    up.roundUp = true;
    EXPECT_EQ(oas::makePattern(up).N, 121u);
}

TEST(OaValidation, InvalidParametersThrow)
{
    // Bush needs q >= t: 2^3 = 8 with t = 3, 3^4 = 81 with t = 4.
    EXPECT_THROW(oas::makePattern(request("bush", 8, 3, 3)), oas::InvalidArgument);
    EXPECT_THROW(oas::makePattern(request("bush", 81, 5, 4)), oas::InvalidArgument);
    // CMJND with more than 24 dims and no strength: one full factorial cannot hold them.
    EXPECT_THROW(oas::makePattern(request("cmjnd", 1u << 10, 30, 0)), oas::InvalidArgument);
    EXPECT_NO_THROW(oas::makePattern(request("cmjnd", 1u << 10, 30, 10)));
    // Bose-Bush needs q a power of two (18 = 2 * 3^2), Addelman-Kempthorne q odd (32 = 2 * 4^2).
    EXPECT_THROW(oas::makePattern(request("bose-bush", 18, 7, 0)), oas::InvalidArgument);
    EXPECT_THROW(oas::makePattern(request("addelman-kempthorne", 32, 9, 0)), oas::InvalidArgument);
    // ... and the swapped requests are fine.
    EXPECT_NO_THROW(oas::makePattern(request("addelman-kempthorne", 18, 7, 0)));
    EXPECT_NO_THROW(oas::makePattern(request("bose-bush", 32, 9, 0)));
    // spp out of [1, 2^24], for every sampler.
    for (const char* name : {"bose", "bush", "bose-bush", "addelman-kempthorne", "cmjnd", "oa"}) {
        EXPECT_THROW(oas::makePattern(request(name, 0, 2, 0)), oas::InvalidArgument) << name;
        EXPECT_THROW(oas::makePattern(request(name, (1u << 24) + 1, 2, 0)), oas::InvalidArgument) << name;
    }
}

}  // namespace
