// The pattern's facts, each with one definition, and the checks that keep the other sides to it:
// the descriptor layout (the C struct OasPattern in host/oas/oas_pattern.h, which oas::Pattern
// derives from, against the GLSL struct in shaders/oas/oas_pattern.glsl), the constants both
// sides name, the sampler names (the C builder's table) and the valid sample counts
// (oas_valid_counts, stated from the construction rules, against trial builds). CPU only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/oas_pattern.h"
#include "oas/pattern.hpp"

#if !defined(OAS_SHADER_DIR) || !defined(OAS_SOURCE_DIR)
#error "define OAS_SHADER_DIR and OAS_SOURCE_DIR"
#endif

namespace {

using Fields = std::vector<std::pair<std::string, std::string>>;  // (type, name) in layout order

// ---- layout ---------------------------------------------------------------------------------

// The field names once more, in layout order, only so that the compiler can check offsets: the
// test below fails unless this list equals both parsed sources, so it cannot fall behind them.
#define OAS_TEST_PATTERN_FIELDS(X)                                                                                               \
    X(construction)                                                                                                              \
    X(offset)                                                                                                                    \
    X(N)                                                                                                                         \
    X(s) X(strength) X(blockDims) X(fieldP) X(fieldK) X(fieldQ) X(fieldPoly) X(aux) X(aux2) X(recipS) X(recipP) X(recipN)        \
        X(recipShifts)

// oas::glsl::OasPattern is the GLSL struct itself, compiled as C++ (glsl_compat.hpp); with uint
// members only, its C++ layout is std430's (4-byte words, no padding).
#define OAS_TEST_SAME_OFFSET(f)                                                                                                  \
    static_assert(offsetof(OasPattern, f) == offsetof(oas::glsl::OasPattern, f), #f);                                            \
    static_assert(offsetof(OasPattern, f) == offsetof(oas::Pattern, f), #f);                                                     \
    static_assert(sizeof(OasPattern::f) == 4 && sizeof(oas::glsl::OasPattern::f) == 4, #f);
OAS_TEST_PATTERN_FIELDS(OAS_TEST_SAME_OFFSET)
#undef OAS_TEST_SAME_OFFSET
static_assert(sizeof(OasPattern) == 64 && sizeof(oas::glsl::OasPattern) == 64 && sizeof(oas::Pattern) == 64);
static_assert(std::is_standard_layout_v<oas::Pattern> && std::is_trivially_copyable_v<oas::Pattern>,
              "oas::Pattern is uploaded and memcpy'd as the C struct");

std::string readFile(const std::string& path)
{
    std::ifstream in(path);
    EXPECT_TRUE(in) << "cannot read " << path;
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string withoutComments(std::string text)
{
    text = std::regex_replace(text, std::regex(R"(/\*[\s\S]*?\*/)"), " ");
    return std::regex_replace(text, std::regex(R"(//[^\n]*)"), " ");
}

// The members between `open` and the next "}" as (type, name); `type a, b;` declares two.
Fields parseMembers(const std::string& source, const std::string& open)
{
    const std::string text = withoutComments(source);
    const std::size_t begin = text.find(open);
    EXPECT_NE(begin, std::string::npos) << "no '" << open << "'";
    if (begin == std::string::npos) return {};
    const std::size_t bodyBegin = begin + open.size();
    const std::string body = text.substr(bodyBegin, text.find('}', bodyBegin) - bodyBegin);
    Fields out;
    std::stringstream declarations(body);
    std::string declaration;
    const std::regex typeThenNames(R"(^\s*(\w+)\s+([\w\s,]+?)\s*$)");
    while (std::getline(declarations, declaration, ';')) {
        if (declaration.find_first_not_of(" \t\r\n") == std::string::npos) continue;
        std::smatch m;
        EXPECT_TRUE(std::regex_match(declaration, m, typeThenNames)) << "cannot read member '" << declaration << "'";
        if (m.empty()) continue;
        std::stringstream names(m[2].str());
        for (std::string name; std::getline(names, name, ',');) {
            name = std::regex_replace(name, std::regex(R"(\s+)"), "");
            out.emplace_back(m[1].str(), name);
        }
    }
    return out;
}

TEST(PatternLayout, GlslStructAndCStructListTheSameFields)
{
    const Fields glsl = parseMembers(readFile(OAS_SHADER_DIR "/oas/oas_pattern.glsl"), "struct OasPattern {");
    Fields c = parseMembers(readFile(OAS_SOURCE_DIR "/host/oas/oas_pattern.h"), "typedef struct OasPattern {");
    ASSERT_EQ(glsl.size(), 16u) << "16 words: the push-constant budget docs/PATTERN.md states";
    // std430 lays out scalar uints as consecutive 4-byte words, as C lays out uint32_t: equal
    // names in equal order with GLSL uint for uint32_t are the same bytes.
    for (auto& [type, name] : c) type = type == "uint32_t" ? "uint" : "C type " + type;
    EXPECT_EQ(c, glsl) << "shaders/oas/oas_pattern.glsl and host/oas/oas_pattern.h disagree";
    std::vector<std::string> checked;
#define OAS_TEST_NAME(f) checked.push_back(#f);
    OAS_TEST_PATTERN_FIELDS(OAS_TEST_NAME)
#undef OAS_TEST_NAME
    std::vector<std::string> names;
    for (auto& field : glsl) names.push_back(field.second);
    EXPECT_EQ(checked, names) << "OAS_TEST_PATTERN_FIELDS must list every field for the offset checks";
}

TEST(PatternLayout, FieldNameTableIsTheStructsFieldList)
{
    const Fields c = parseMembers(readFile(OAS_SOURCE_DIR "/host/oas/oas_pattern.h"), "typedef struct OasPattern {");
    std::vector<std::string> fromStruct, fromTable;
    for (const auto& field : c) fromStruct.push_back(field.second);
    for (std::size_t word = 0; oas_pattern_field_name(word); ++word) fromTable.push_back(oas_pattern_field_name(word));
    EXPECT_EQ(fromTable, fromStruct) << "oas_pattern_field_name must name the struct's words in order";
}

TEST(PatternLayout, SpecificationPageListsTheStructsWords)
{
    // docs/PATTERN.md is the specification ports implement, so it states the layout for readers;
    // its word table ("| # | `name` |" rows) must be the struct's field list, number for number.
    const std::string page = readFile(OAS_SOURCE_DIR "/docs/PATTERN.md");
    const std::regex row(R"(\n\| (\d+) \| `(\w+)` \|)");
    std::vector<std::string> documented;
    for (auto it = std::sregex_iterator(page.begin(), page.end(), row); it != std::sregex_iterator(); ++it) {
        EXPECT_EQ(std::stoul((*it)[1]), documented.size()) << "word numbers must count up from 0";
        documented.push_back((*it)[2]);
    }
    std::vector<std::string> fromStruct;
    for (const auto& field : parseMembers(readFile(OAS_SOURCE_DIR "/host/oas/oas_pattern.h"), "typedef struct OasPattern {"))
        fromStruct.push_back(field.second);
    EXPECT_EQ(documented, fromStruct) << "docs/PATTERN.md's word table and host/oas/oas_pattern.h disagree";
}

TEST(PatternLayout, ParserReadsWhatItIsGiven)
{
    // The check above is only as good as the parser: a field added on one side must show.
    const Fields f = parseMembers("struct S { uint a; /* x */ uint32_t b, c; // y\n uint d; };", "struct S {");
    EXPECT_EQ(f, (Fields{{"uint", "a"}, {"uint32_t", "b"}, {"uint32_t", "c"}, {"uint", "d"}}));
}

TEST(PatternLayout, PatternIsTheCStructWordForWord)
{
    OasPattern built;
    ASSERT_EQ(oas_make_pattern(OAS_ADDELMAN_KEMPTHORNE, 162, 0, OAS_OFFSET_MJ, &built, nullptr, 0), 0);
    const oas::Pattern viaCpp = oas::makePattern({.sampler = "addelman-kempthorne", .spp = 162, .offset = "mj"});
    EXPECT_EQ(std::memcmp(&built, &viaCpp, sizeof built), 0);
    const oas::glsl::OasPattern glsl = oas::glsl::toGlsl(viaCpp);
    EXPECT_EQ(glsl.aux, built.aux);
    EXPECT_EQ(glsl.recipShifts, built.recipShifts);
    const oas::Pattern zero;
    for (int i = 0; i < 16; ++i) EXPECT_EQ((&zero.construction)[i], 0u) << "a default oas::Pattern is all zeros";
}

// ---- constants both sides name ---------------------------------------------------------------

// The GLSL library restates the C header's codes and block sizes (GLSL cannot include C); the
// compiled GLSL must agree with the header, value for value.
static_assert(oas::glsl::OAS_BOSE == OAS_BOSE && oas::glsl::OAS_BUSH == OAS_BUSH && oas::glsl::OAS_BOSE_BUSH == OAS_BOSE_BUSH &&
              oas::glsl::OAS_ADDELMAN_KEMPTHORNE == OAS_ADDELMAN_KEMPTHORNE && oas::glsl::OAS_CMJND == OAS_CMJND &&
              oas::glsl::OAS_RANDOM == OAS_RANDOM && oas::glsl::OAS_JITTERED_2D == OAS_JITTERED_2D &&
              oas::glsl::OAS_CMJ_2D == OAS_CMJ_2D && oas::glsl::OAS_ZERO_TWO == OAS_ZERO_TWO &&
              oas::glsl::OAS_HALTON == OAS_HALTON && oas::glsl::OAS_SOBOL == OAS_SOBOL &&
                  oas::glsl::OAS_SOBOL_OWEN == OAS_SOBOL_OWEN && oas::glsl::OAS_SOBOL_BURLEY == OAS_SOBOL_BURLEY &&
                  oas::glsl::OAS_FAURE == OAS_FAURE);
static_assert(oas::glsl::OAS_OFFSET_CENTERED == OAS_OFFSET_CENTERED && oas::glsl::OAS_OFFSET_J == OAS_OFFSET_J &&
              oas::glsl::OAS_OFFSET_MJ == OAS_OFFSET_MJ && oas::glsl::OAS_OFFSET_CMJ == OAS_OFFSET_CMJ);
static_assert(oas::glsl::OAS_HALTON_BLOCK == OAS_HALTON_BLOCK_DIMS, "shaders/oas/oas_baselines.glsl's Halton block");
static_assert(oas::glsl::OAS_SOBOL_BLOCK == OAS_SOBOL_BLOCK_DIMS, "shaders/oas/oas_baselines.glsl's Sobol block");
static_assert(oas::glsl::OAS_SOBOL_BURLEY_GROUP == OAS_SOBOL_BURLEY_GROUP_DIMS, "oas_baselines.glsl's Sobol-Burley group");
static_assert(oas::glsl::OAS_FAURE_MAX_DIGITS == OAS_FAURE_MAX_DIGITS, "shaders/oas/oas_faure.glsl's most index digits");

TEST(PatternConstants, BaselinesUseTheHeadersBlockSizes)
{
    EXPECT_EQ(oas::makePattern({.sampler = "halton", .spp = 7}).blockDims, std::uint32_t(OAS_HALTON_BLOCK_DIMS));
    EXPECT_EQ(oas::makePattern({.sampler = "sobol", .spp = 7}).blockDims, std::uint32_t(OAS_SOBOL_BLOCK_DIMS));
    EXPECT_EQ(oas::makePattern({.sampler = "sobol-owen", .spp = 7}).blockDims, std::uint32_t(OAS_SOBOL_BLOCK_DIMS));
    EXPECT_EQ(oas::makePattern({.sampler = "sobol-burley", .spp = 7}).blockDims, std::uint32_t(OAS_SOBOL_BURLEY_GROUP_DIMS));
    EXPECT_EQ(oas::sobolDirections().size(), std::size_t(OAS_SOBOL_BLOCK_DIMS) * 32);
}

// ---- names ------------------------------------------------------------------------------------

TEST(PatternNames, CppListsTheCBuildersNamesInItsOrder)
{
    std::vector<std::string> fromC;
    for (std::size_t i = 0; oas_construction_at(i) != 0; ++i) fromC.push_back(oas_construction_name(oas_construction_at(i)));
    EXPECT_EQ(oas::samplerNames(), fromC);
    EXPECT_EQ(fromC, (std::vector<std::string>{"bose", "bush", "bose-bush", "addelman-kempthorne", "cmjnd", "random",
                                               "jittered2d", "cmj2d", "zerotwo", "halton", "sobol", "sobol-owen",
                                               "sobol-burley", "faure"}));
    for (std::size_t i = 0; oas_construction_at(i) != 0; ++i) {
        const std::uint32_t code = oas_construction_at(i);
        std::uint32_t back = 0;
        EXPECT_EQ(oas_construction_from_name(oas_construction_name(code), &back), 0);
        EXPECT_EQ(back, code);
        EXPECT_EQ(oas::constructionName(code), fromC[i]);
        EXPECT_EQ(oas::isOrthogonalArray(fromC[i]), code < OAS_RANDOM) << fromC[i];
        EXPECT_NE(oas::samplerDescription(fromC[i]), fromC[i]) << "every sampler has a description";
    }
    EXPECT_EQ(oas::constructionName(6), "unknown(6)");
    EXPECT_THROW(oas::samplerDescription("Bose"), oas::InvalidArgument);
}

TEST(PatternNames, DescriptionsQuoteTheLibrarysNumbers)
{
    EXPECT_EQ(oas::samplerDescription("bose"),
              "Bose OA(q^2, q+1, q, 2), q prime power <= 4096: N = 4, 9, 16, 25, 49, 64, 81, 121 ...");
    EXPECT_EQ(oas::samplerDescription("bose-bush"), "Bose-Bush OA(2q^2, 2q+1, q, 2), q = 2^k: N = 8, 32, 128, 512, 2048 ...");
    EXPECT_EQ(oas::samplerDescription("addelman-kempthorne"),
              "Addelman-Kempthorne OA(2q^2, 2q+1, q, 2), q odd prime power: N = 18, 50, 98, 162 ...");
    EXPECT_EQ(oas::samplerDescription("halton"), "Halton with random digit permutations, blocks of 32 dims (baseline)");
    EXPECT_EQ(oas::samplerDescription("sobol"),
              "Owen-scrambled Sobol, hash-based scramble (after Burley 2020), blocks of 1024 dims (baseline; Joe-Kuo direction "
              "numbers)");
}

// ---- valid counts -----------------------------------------------------------------------------

std::vector<std::uint32_t> ruleCounts(std::uint32_t code, std::uint32_t t, std::uint32_t lo, std::uint32_t hi)
{
    std::vector<std::uint32_t> out(oas_valid_counts(code, t, lo, hi, nullptr, 0));
    EXPECT_EQ(oas_valid_counts(code, t, lo, hi, out.data(), out.size()), out.size());
    return out;
}

// The independent check: every n in [lo, hi] tried on the builder itself.
std::vector<std::uint32_t> builtCounts(std::uint32_t code, std::uint32_t t, std::uint32_t lo, std::uint32_t hi)
{
    std::vector<std::uint32_t> out;
    OasPattern p;
    for (std::uint32_t n = lo; n <= hi; ++n)
        if (oas_make_pattern(code, n, t, OAS_OFFSET_CMJ, &p, nullptr, 0) == OAS_PATTERN_OK) out.push_back(n);
    return out;
}

TEST(PatternCounts, RulesMatchTrialBuildsForEveryConstructionAndStrength)
{
    // Every construction (and an unknown code) at every strength, default included, over the
    // counts up to 2^16; the strength-2 OAs again over the whole range below, where the field
    // limits (GF(3^6) first, at 729^2) start to bite.
    const std::uint32_t hi = 1u << 16;
    std::vector<std::uint32_t> codes = {6, 22};
    for (std::size_t i = 0; oas_construction_at(i) != 0; ++i) codes.push_back(oas_construction_at(i));
    for (std::uint32_t code : codes)
        for (std::uint32_t t = 0; t <= OAS_MAX_STRENGTH + 1; ++t) {
            const auto built = builtCounts(code, t, 1, hi);
            EXPECT_EQ(ruleCounts(code, t, 1, hi), built) << "construction " << code << ", strength " << t;
            if (code >= OAS_RANDOM && code != OAS_FAURE && oas_construction_name(code) != nullptr && t <= OAS_MAX_STRENGTH) {
                EXPECT_EQ(built.size(), hi) << "the baselines take any count";
            }
        }
    // Faure takes any count up to its longest sequence, q^K with K <= 12 digits: base 2 (d <= 2,
    // the default 0 included) stops at 2^12; base 3 (d = 3) at 3^12 = 531441, past this range.
    for (std::uint32_t t : {0u, 1u, 2u}) EXPECT_EQ(builtCounts(OAS_FAURE, t, 1, hi).size(), 4096u) << t;
    EXPECT_EQ(builtCounts(OAS_FAURE, 3, 1, hi).size(), hi);
}

TEST(PatternCounts, RulesMatchTrialBuildsOverTheWholeRange)
{
    for (std::uint32_t code : {OAS_BOSE, OAS_BUSH, OAS_BOSE_BUSH, OAS_ADDELMAN_KEMPTHORNE})
        EXPECT_EQ(ruleCounts(code, 2, 1, OAS_MAX_SAMPLES), builtCounts(code, 2, 1, OAS_MAX_SAMPLES)) << code;
    // Higher strengths have q <= 256, below every field limit: one of them suffices here.
    EXPECT_EQ(ruleCounts(OAS_BUSH, 3, 1, OAS_MAX_SAMPLES), builtCounts(OAS_BUSH, 3, 1, OAS_MAX_SAMPLES));
    // Bose leaves out q = 729 = 3^6, whose field the shaders cannot multiply in one word.
    const auto bose = ruleCounts(OAS_BOSE, 2, 1, OAS_MAX_SAMPLES);
    EXPECT_EQ(std::count(bose.begin(), bose.end(), 729u * 729u), 0);
    EXPECT_EQ(std::count(bose.begin(), bose.end(), 4096u * 4096u), 1);
}

TEST(PatternCounts, RangeAndCapacity)
{
    EXPECT_EQ(ruleCounts(OAS_BOSE, 2, 10, 100), (std::vector<std::uint32_t>{16, 25, 49, 64, 81}));
    EXPECT_EQ(ruleCounts(OAS_BOSE, 2, 100, 10), std::vector<std::uint32_t>{});
    EXPECT_EQ(ruleCounts(OAS_CMJND, 0, 1, 1000), std::vector<std::uint32_t>{}) << "cmjnd has no default strength";
    std::uint32_t first[3] = {0, 0, 0};
    EXPECT_EQ(oas_valid_counts(OAS_BOSE_BUSH, 0, 0, 1000, first, 2), 4u) << "8, 32, 128, 512";
    EXPECT_EQ(first[0], 8u);
    EXPECT_EQ(first[1], 32u);
    EXPECT_EQ(first[2], 0u) << "nothing past capacity";
    EXPECT_EQ(oas_valid_counts(OAS_HALTON, 0, 5, OAS_MAX_SAMPLES + 100u, nullptr, 0), std::size_t(OAS_MAX_SAMPLES) - 4);
    EXPECT_EQ(oas_valid_counts(OAS_HALTON, 0, 5, 9, first, 3), 5u);
    EXPECT_EQ(first[0], 5u);
    EXPECT_EQ(first[2], 7u);
}

TEST(PatternCounts, CppValidCountsAreTheCRules)
{
    for (const auto& name : oas::samplerNames()) {
        std::uint32_t code = 0;
        ASSERT_EQ(oas_construction_from_name(name.c_str(), &code), 0);
        const std::uint32_t t = code == OAS_CMJND ? 3 : 2;
        auto rules = ruleCounts(code, t, 1, 5000);
        if (code >= OAS_RANDOM) rules.resize(64);  // validCounts lists the first 64 of a baseline's range
        EXPECT_EQ(oas::validCounts(name, t, 3, 1, 5000), rules) << name;
    }
}

}  // namespace

TEST(PatternLayout, PairDimensionIsTheFirstEvenColumnPairOfABlock)
{
    // The contract of oas_pair_dimension (oas_pattern.h), checked from its statement for every
    // sampler at block sizes odd and even: d >= from, (d, d + 1) in one block, d at an even column
    // of it, and no smaller such d; random (one-dimension blocks) returns from. The GLSL twin
    // gives the same for every from.
    std::size_t oddBlocks = 0;
    for (const auto& name : oas::samplerNames()) {
        for (std::uint32_t spp : {16u, 32u, 49u, 64u, 81u, 98u, 128u, 162u}) {
            std::uint32_t code = 0;
            ASSERT_EQ(oas_construction_from_name(name.c_str(), &code), 0) << name;
            OasPattern built;
            char reason[256];
            if (oas_make_pattern(code, spp, name == "cmjnd" ? 2 : 0, OAS_OFFSET_CMJ, &built, reason, sizeof reason) != 0) continue;
            const std::uint32_t blockDims = built.blockDims;
            oddBlocks += blockDims % 2;
            const std::uint32_t span = std::min<std::uint32_t>(4 * blockDims + 4, 5000);
            for (std::uint32_t from = 0; from < span; ++from) {
                const std::uint32_t d = oas_pair_dimension(&built, from);
                ASSERT_EQ(d, oas::glsl::oas_pair_dimension(oas::glsl::toGlsl(oas::Pattern(built)), from)) << name << " " << spp;
                if (blockDims < 2) {
                    ASSERT_EQ(d, from) << name;
                    continue;
                }
                auto isPair = [&](std::uint32_t x) { return x / blockDims == (x + 1) / blockDims && (x % blockDims) % 2 == 0; };
                ASSERT_GE(d, from) << name << " " << spp;
                ASSERT_TRUE(isPair(d)) << name << " " << spp << " from " << from << " gave " << d;
                for (std::uint32_t x = from; x < d; ++x) ASSERT_FALSE(isPair(x)) << name << " " << spp << ": " << x << " < " << d;
            }
        }
    }
    EXPECT_GT(oddBlocks, 0u) << "no odd block size covered (Bose-Bush and Addelman-Kempthorne have 2q + 1)";
}
