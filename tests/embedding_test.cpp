// The GLSL library (shaders/oas/*.glsl) must drop into another renderer's shader: no #version,
// layout, #extension or binding of its own, and every top-level name it declares (function,
// struct, const, global, #define) prefixed oas_ / Oas / OAS_, so it cannot collide with the
// host shader's names. Checked three ways:
//   - tests/shaders/other_renderer.comp, a shader that defines hash, permute, random, rand, pcg,
//     hash2, fastdiv, mulhi, Pattern, Field, Row, ONE and N itself, includes oas/oas.glsl and must
//     compile with glslangValidator;
//   - a line scanner over every library file (with negative controls showing it can fail);
//   - the C++ twin (oas/glsl_compat.hpp) compiling the same files into this test.
// Paths come from the compile definitions OAS_SHADER_DIR, OAS_TEST_SHADER_DIR, OAS_GLSLANG and
// OAS_SINGLE_GLSL (the generated single-file library, checked against the includes here too).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"

#if !defined(OAS_SHADER_DIR) || !defined(OAS_TEST_SHADER_DIR) || !defined(OAS_GLSLANG) || !defined(OAS_SINGLE_GLSL)
#error "define OAS_SHADER_DIR, OAS_TEST_SHADER_DIR, OAS_GLSLANG and OAS_SINGLE_GLSL"
#endif

namespace {

namespace fs = std::filesystem;

// ------------------------------------------------------------------------------------ scanner

struct Finding {
    std::string file;
    int line = 0;
    std::string what;
};

std::string format(const std::vector<Finding>& findings)
{
    std::string out;
    for (auto& f : findings) out += "  " + f.file + ":" + std::to_string(f.line) + ": " + f.what + "\n";
    return out;
}

/// Removes // and /* */ comments, keeping every newline so line numbers stay right. (The library's
/// documentation shows how to embed it, `layout(push_constant)` included; only code counts.)
std::string stripComments(const std::string& text)
{
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        if (text.compare(i, 2, "//") == 0) {
            while (i < text.size() && text[i] != '\n') ++i;
        } else if (text.compare(i, 2, "/*") == 0) {
            i += 2;
            while (i < text.size() && text.compare(i, 2, "*/") != 0) {
                if (text[i] == '\n') out += '\n';
                ++i;
            }
            i = std::min(text.size(), i + 2);
            out += ' ';
        } else {
            out += text[i++];
        }
    }
    return out;
}

bool hasLibraryPrefix(const std::string& name)
{
    return name.rfind("oas_", 0) == 0 || name.rfind("Oas", 0) == 0 || name.rfind("OAS_", 0) == 0;
}

struct ScanResult {
    std::vector<Finding> findings;
    std::vector<std::string> names;  ///< every top-level name the scan recognised
};

/// Scans GLSL source meant for embedding. Flags #version, #extension, layout( and binding on any
/// code line, and any top-level (brace depth 0) function, struct, const, global variable or
/// #define whose name lacks the library prefix.
ScanResult scanGlsl(const std::string& text, const std::string& file)
{
    static const std::regex version(R"(^\s*#\s*version\b)");
    static const std::regex extension(R"(^\s*#\s*extension\b)");
    static const std::regex layout(R"(\blayout\s*\()");
    static const std::regex binding(R"(\bbinding\b)");
    static const std::string qualifiers =
        R"((?:(?:highp|mediump|lowp|precise|invariant|shared|uniform|buffer|in|out|coherent|volatile|restrict|readonly|writeonly)\s+)*)";
    static const std::regex define(R"(^\s*#\s*define\s+([A-Za-z_]\w*))");
    static const std::regex structDecl(R"(^\s*struct\s+([A-Za-z_]\w*))");
    static const std::regex constDecl(
        R"(^\s*const\s+(?:(?:highp|mediump|lowp|precise)\s+)*[A-Za-z_]\w*(?:\s*\[[^\]]*\])?\s+([A-Za-z_]\w*)\s*(?:\[[^\]]*\])?\s*=)");
    static const std::regex function("^\\s*" + qualifiers + R"(([A-Za-z_]\w*)\s+([A-Za-z_]\w*)\s*\()");
    static const std::regex global("^\\s*" + qualifiers + R"(([A-Za-z_]\w*)\s+([A-Za-z_]\w*)\s*(?:\[[^\]]*\])?\s*[=;,])");

    ScanResult result;
    std::istringstream in(stripComments(text));
    int depth = 0;
    int lineNo = 0;
    for (std::string line; std::getline(in, line);) {
        ++lineNo;
        auto flag = [&](const std::string& what) { result.findings.push_back({file, lineNo, what}); };
        if (std::regex_search(line, version)) flag("#version (the embedding shader owns it)");
        if (std::regex_search(line, extension)) flag("#extension (the embedding shader owns it)");
        if (std::regex_search(line, layout)) flag("layout( qualifier (the embedding shader owns its interface)");
        if (std::regex_search(line, binding)) flag("'binding' (the embedding shader owns its bindings)");

        if (depth == 0) {
            std::smatch m;
            std::string kind, name;
            if (std::regex_search(line, m, define)) {
                kind = "#define";
                name = m[1];
            } else if (std::regex_search(line, m, structDecl)) {
                kind = "struct";
                name = m[1];
            } else if (std::regex_search(line, m, constDecl)) {
                kind = "const";
                name = m[1];
            } else if (std::regex_search(line, m, function) && m[1] != "return" && m[1] != "else" && m[1] != "const") {
                kind = "function";
                name = m[2];
            } else if (std::regex_search(line, m, global) && m[1] != "return" && m[1] != "const" && m[1] != "struct") {
                kind = "global";
                name = m[2];
            }
            if (!name.empty()) {
                result.names.push_back(name);
                if (!hasLibraryPrefix(name)) flag(kind + " '" + name + "' lacks the oas_ / Oas / OAS_ prefix");
            }
        }
        if (line.find_first_not_of(" \t") != std::string::npos && line[line.find_first_not_of(" \t")] == '#') continue;
        for (char c : line) {
            if (c == '{') ++depth;
            if (c == '}') --depth;
        }
        if (depth < 0) {
            flag("unbalanced '}'");
            depth = 0;
        }
    }
    if (depth != 0) result.findings.push_back({file, lineNo, "unbalanced braces at end of file"});
    return result;
}

std::string readFile(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::vector<fs::path> libraryFiles()
{
    std::vector<fs::path> files;
    for (auto& e : fs::directory_iterator(fs::path(OAS_SHADER_DIR) / "oas"))
        if (e.is_regular_file() && e.path().extension() == ".glsl") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

bool flagged(const ScanResult& r, int line, const std::string& word)
{
    for (auto& f : r.findings)
        if (f.line == line && f.what.find(word) != std::string::npos) return true;
    return false;
}

// --------------------------------------------------------------------------- compile the shader

std::string shellQuote(const std::string& s)
{
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

TEST(Embedding, OtherRendererShaderCompilesWithGlslang)
{
    const fs::path source = fs::path(OAS_TEST_SHADER_DIR) / "other_renderer.comp";
    ASSERT_TRUE(fs::exists(source)) << source;
    const fs::path spv = fs::temp_directory_path() / ("oas_other_renderer_" + std::to_string(::getpid()) + ".spv");
    const std::string command = shellQuote(OAS_GLSLANG) + " --target-env vulkan1.1 -I" + shellQuote(OAS_SHADER_DIR) + " -o " +
                                shellQuote(spv.string()) + " " + shellQuote(source.string()) + " 2>&1";
    std::FILE* pipe = ::popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr) << command;
    std::string output;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) output.append(buf, n);
    const int status = ::pclose(pipe);
    const std::string bytes = readFile(spv);
    std::error_code ec;
    fs::remove(spv, ec);
    const bool compiled = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    ASSERT_TRUE(compiled) << "glslangValidator failed: " << command << "\n" << output;
    ASSERT_GE(bytes.size(), 20u) << "no SPIR-V written\n" << output;
    std::uint32_t magic;
    std::memcpy(&magic, bytes.data(), 4);
    EXPECT_EQ(magic, 0x07230203u) << "not a SPIR-V module";
}

/// Runs glslangValidator on a shader text; returns (exit status 0?, its output), and the SPIR-V
/// module's bytes in *spirv when given.
std::pair<bool, std::string> compileText(const std::string& text, std::string* spirv = nullptr)
{
    const std::string stem = "oas_embed_" + std::to_string(::getpid());
    const fs::path source = fs::temp_directory_path() / (stem + ".comp");
    const fs::path spv = fs::temp_directory_path() / (stem + ".spv");
    {
        std::FILE* f = std::fopen(source.c_str(), "w");
        if (!f) return {false, "cannot write " + source.string()};
        std::fputs(text.c_str(), f);
        std::fclose(f);
    }
    const std::string command = shellQuote(OAS_GLSLANG) + " --target-env vulkan1.1 -I" + shellQuote(OAS_SHADER_DIR) + " -o " +
                                shellQuote(spv.string()) + " " + shellQuote(source.string()) + " 2>&1";
    std::FILE* pipe = ::popen(command.c_str(), "r");
    std::string output;
    if (pipe) {
        char buf[4096];
        for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) output.append(buf, n);
    }
    const int status = pipe ? ::pclose(pipe) : -1;
    if (spirv) *spirv = fs::exists(spv) ? readFile(spv) : std::string();
    std::error_code ec;
    fs::remove(source, ec);
    fs::remove(spv, ec);
    return {WIFEXITED(status) && WEXITSTATUS(status) == 0, output};
}

TEST(Embedding, SingleFileIsTheLibraryWithoutIncludes)
{
    // oas_single.glsl (generated by cmake/oas_single_glsl.cmake) must need no #include support and
    // be the same library: with the same #extension lines, a shader built on it compiles to the
    // same SPIR-V, byte for byte, as one that includes oas/oas.glsl.
    const std::string single = readFile(OAS_SINGLE_GLSL);
    ASSERT_GT(single.size(), 10000u) << OAS_SINGLE_GLSL;
    EXPECT_EQ(single.find("\n#include"), std::string::npos) << "an #include directive survived";
    const std::string extensions =
        "#extension GL_GOOGLE_include_directive : require\n#extension GL_EXT_control_flow_attributes : require\n";
    const std::string main =
        "layout(local_size_x = 8) in;\n"
        "layout(std430, binding = 0) writeonly buffer Out { float v[]; };\n"
        "layout(push_constant) uniform P { OasPattern pattern; } params;\n"
        "void main() {\n"
        "  uint seed = oas_pixel_seed(gl_GlobalInvocationID.x, 0u, 7u);\n"
        "  OasRow row = oas_row(params.pattern, seed, gl_GlobalInvocationID.y, 0u);\n"
        "  v[gl_GlobalInvocationID.x * 3u] = oas_row_dim(params.pattern, row, 1u);\n"
        "  v[gl_GlobalInvocationID.x * 3u + 1u] = oas_sample(params.pattern, seed, gl_GlobalInvocationID.y, 5u);\n"
        "}\n";
    std::string included, inlined;
    const auto [a, aMessage] =
        compileText("#version 450\n" + extensions + "#define OAS_NO_SOBOL\n#include \"oas/oas.glsl\"\n" + main, &included);
    ASSERT_TRUE(a) << aMessage;
    const auto [b, bMessage] = compileText("#version 450\n" + extensions + "#define OAS_NO_SOBOL\n" + single + main, &inlined);
    ASSERT_TRUE(b) << bMessage;
    EXPECT_GT(included.size(), 1000u);
    EXPECT_TRUE(included == inlined) << "SPIR-V differs: " << included.size() << " vs " << inlined.size() << " bytes";
    const auto [bare, bareMessage] =
        compileText("#version 450\n#extension GL_EXT_control_flow_attributes : require\n#define OAS_NO_SOBOL\n" + single + main);
    EXPECT_TRUE(bare) << "without GL_GOOGLE_include_directive: " << bareMessage;
}

TEST(Embedding, SobolWithoutDirectionNumbersIsACompileError)
{
    // The Sobol baseline needs its direction numbers from the includer. A silent fallback would
    // hand out values that are not Sobol's, so the includer must choose (or define OAS_NO_SOBOL).
    const std::string head =
        "#version 450\n#extension GL_GOOGLE_include_directive : require\n#extension GL_EXT_control_flow_attributes : require\n";
    const std::string body = "#include \"oas/oas.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n";
    const auto [neither, message] = compileText(head + body);
    EXPECT_FALSE(neither) << "compiled without OAS_SOBOL_DIRECTION or OAS_NO_SOBOL";
    EXPECT_NE(message.find("OAS_SOBOL_DIRECTION"), std::string::npos) << message;
    const auto [optedOut, optedOutMessage] = compileText(head + "#define OAS_NO_SOBOL\n" + body);
    EXPECT_TRUE(optedOut) << optedOutMessage;
    const auto [withTable, withTableMessage] = compileText(head +
                                                           "layout(std430, binding = 0) readonly buffer D { uint d[]; };\n"
                                                           "#define OAS_SOBOL_DIRECTION(dim, bit) d[(dim) * 32u + (bit)]\n" +
                                                           body);
    EXPECT_TRUE(withTable) << withTableMessage;
}

TEST(Embedding, TheHeaderListsExactlyTheMacroNamesThatBreakIt)
{
    // The header's list of names an includer must not have as object-like macros is checked
    // both ways: each listed name breaks the include, and common renderer macros outside the list
    // (a sample of them) do not. A rename that makes a name safe must update the header.
    const std::vector<std::string> listed = {
        "N",        "K",        "i",     "j",       "k",       "l",      "m",    "n",     "p",     "q",
        "r",        "s",        "t",     "u",       "v",       "x",      "y",    "seed",  "index", "offset",
        "dim",      "pass",     "row",   "col",     "level",   "block",  "key",  "hi",    "lo",    "bits",
        "mask",     "shift",    "f",     "g",       "a",       "b",      "c",    "d",     "e",     "h",
        "sub",      "rotation", "pivot", "partner", "stratum", "jitter", "base", "digit", "power", "construction",
        "strength", "aux",      "fieldP"};
    const std::vector<std::string> safe = {"M", "L",     "S",  "T",   "P",   "Q",    "R",   "A",   "B",     "C",  "D", "E",
                                           "F", "G",     "H",  "I",   "J",   "U",    "V",   "W",   "X",     "Y",  "Z", "w",
                                           "z", "count", "PI", "EPS", "ONE", "ZERO", "MAX", "MIN", "value", "sum"};
    // The header's list: the words between "glslangValidator):" and "Undefine", minus "//".
    const std::string header = readFile(fs::path(OAS_SHADER_DIR) / "oas" / "oas.glsl");
    const std::size_t from = header.find("glslangValidator):"), to = header.find("Undefine", from);
    ASSERT_NE(from, std::string::npos);
    ASSERT_NE(to, std::string::npos);
    std::vector<std::string> documented;
    {
        std::istringstream words(header.substr(from + 18, to - from - 18));
        for (std::string w; words >> w;)
            if (w != "//") documented.push_back(w);
    }
    EXPECT_EQ(documented, listed) << "the header's list and this test's differ";
    const std::string shader = "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                               "#extension GL_EXT_control_flow_attributes : require\n#define OAS_NO_SOBOL\n";
    const std::string body = "#include \"oas/oas.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n";
    for (const std::string& name : listed) {
        EXPECT_FALSE(compileText(shader + "#define " + name + " 7u\n" + body).first)
            << "#define " << name << " no longer breaks the include: drop it from the header's list";
    }
    for (const std::string& name : safe)
        EXPECT_TRUE(compileText(shader + "#define " + name + " 7u\n" + body).first)
            << "#define " << name << " breaks the include";
}

// ------------------------------------------------------------------------------- scan the files

TEST(Embedding, LibraryFilesDeclareOnlyPrefixedNamesAndNoInterface)
{
    const auto files = libraryFiles();
    ASSERT_FALSE(files.empty()) << "no .glsl files in " << OAS_SHADER_DIR << "/oas";
    std::vector<std::string> fileNames;
    for (auto& f : files) fileNames.push_back(f.filename().string());
    for (const char* expected : {"oas.glsl", "oas_hash.glsl", "oas_intdiv.glsl", "oas_permute.glsl", "oas_strata.glsl",
                                 "oas_gf.glsl", "oas_pattern.glsl", "oas_oa.glsl", "oas_baselines.glsl", "oas_draw.glsl",
                                 "oas_faure.glsl"})
        EXPECT_NE(std::find(fileNames.begin(), fileNames.end(), expected), fileNames.end()) << expected << " not scanned";

    std::vector<Finding> findings;
    std::vector<std::string> names;
    for (auto& path : files) {
        const ScanResult r = scanGlsl(readFile(path), "shaders/oas/" + path.filename().string());
        findings.insert(findings.end(), r.findings.begin(), r.findings.end());
        names.insert(names.end(), r.names.begin(), r.names.end());
    }
    EXPECT_TRUE(findings.empty()) << findings.size() << " offender(s):\n" << format(findings);

    // The scan must actually see the library's declarations, or a passing scan means nothing.
    for (const char* name :
         {"oas_sample", "oas_pixel_seed", "oas_row", "oas_row_dim", "oas_pcg", "oas_permute", "oas_draw", "OasDraw",
          "OAS_DRAW_MAX", "OasPattern", "OasRow", "OasField", "OAS_BOSE", "OAS_INV_2POW24", "OAS_GLSL", "OAS_CONSTRUCTION"})
        EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << "scanner did not see '" << name << "'";
    EXPECT_GE(names.size(), 50u);
}

TEST(Embedding, ScannerFlagsForeignNamesNegativeControl)
{
    const ScanResult r = scanGlsl("uint hash(uint x)\n{\n    return x;\n}\n", "synthetic.glsl");
    ASSERT_EQ(r.findings.size(), 1u) << format(r.findings);
    EXPECT_EQ(r.findings[0].line, 1);
    EXPECT_NE(r.findings[0].what.find("'hash'"), std::string::npos) << format(r.findings);
    EXPECT_NE(r.findings[0].what.find("function"), std::string::npos) << format(r.findings);
}

TEST(Embedding, ScannerFlagsEveryKindOfOffence)
{
    const std::string text = "#version 450\n"                                                    // 1
                             "#extension GL_GOOGLE_include_directive : require\n"                // 2
                             "layout(local_size_x = 64) in;\n"                                   // 3
                             "struct Pattern {\n"                                                // 4
                             "    uint n;\n"                                                     // 5
                             "};\n"                                                              // 6
                             "const uint ONE = 1u;\n"                                            // 7
                             "#define N 16\n"                                                    // 8
                             "uint counter;\n"                                                   // 9
                             "float random(uint seed) { return 0.5; }\n"                         // 10
                             "Pattern makePattern(uint n)\n"                                     // 11
                             "{\n"                                                               // 12
                             "    Pattern p;\n"                                                  // 13
                             "    return p;\n"                                                   // 14
                             "}\n"                                                               // 15
                             "layout(std430, set = 0, binding = 1) buffer B { float v[]; };\n";  // 16
    const ScanResult r = scanGlsl(text, "synthetic.glsl");
    EXPECT_TRUE(flagged(r, 1, "#version")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 2, "#extension")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 3, "layout(")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 4, "struct 'Pattern'")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 7, "const 'ONE'")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 8, "#define 'N'")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 9, "global 'counter'")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 10, "function 'random'")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 11, "function 'makePattern'")) << format(r.findings);
    EXPECT_FALSE(flagged(r, 13, "")) << "locals inside a body are not top-level\n" << format(r.findings);
    EXPECT_TRUE(flagged(r, 16, "layout(")) << format(r.findings);
    EXPECT_TRUE(flagged(r, 16, "binding")) << format(r.findings);
}

TEST(Embedding, ScannerIgnoresCommentsBodiesAndPrefixedNames)
{
    const std::string text = "// uint hash(uint x) and layout(binding = 0) in a comment\n"
                             "/* struct Pattern {\n"
                             "   #version 450 */\n"
                             "#ifndef OAS_THING\n"
                             "#define OAS_THING\n"
                             "const uint OAS_ONE = 1u;\n"
                             "struct OasThing {\n"
                             "    uint hash;\n"
                             "    uint N;\n"
                             "};\n"
                             "uint oas_thing(uint x)\n"
                             "{\n"
                             "    uint hash = x;\n"
                             "    const uint N = 3u;\n"
                             "    return hash + N;\n"
                             "}\n"
                             "#endif\n";
    const ScanResult r = scanGlsl(text, "synthetic.glsl");
    EXPECT_TRUE(r.findings.empty()) << format(r.findings);
    for (const char* name : {"OAS_THING", "OAS_ONE", "OasThing", "oas_thing"})
        EXPECT_NE(std::find(r.names.begin(), r.names.end(), name), r.names.end()) << name;
}

// -------------------------------------------------------------------------------- the C++ twin

/// Jarzynski and Olano's PCG hash, written out independently of the library.
std::uint32_t referencePcg(std::uint32_t v)
{
    const std::uint32_t state = v * 747796405u + 2891336453u;
    const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

TEST(Embedding, CppTwinCompilesTheSameFiles)
{
    for (std::uint32_t v : {0u, 1u, 2u, 12345u, 0x80000000u, 0xffffffffu}) EXPECT_EQ(oas::glsl::oas_pcg(v), referencePcg(v)) << v;
    EXPECT_EQ(oas::glsl::OAS_BOSE, 1u);
    EXPECT_EQ(sizeof(oas::glsl::OasPattern), 64u);

    // oas_sample compiled into this translation unit agrees with the library's own copy (oas::sample).
    oas::PatternRequest request;
    request.sampler = "bose";
    request.spp = 49;
    request.dims = 5;
    const oas::Pattern pattern = oas::makePattern(request);
    oas::glsl::OasPattern glslPattern;
    static_assert(sizeof(glslPattern) == sizeof(pattern));
    std::memcpy(&glslPattern, &pattern, sizeof pattern);
    const std::uint32_t seed = oas::glsl::oas_pixel_seed(3u, 4u, 7u);
    EXPECT_EQ(seed, oas::pixelSeed(3, 4, 7));
    for (std::uint32_t i = 0; i < 60; ++i) {
        for (std::uint32_t d = 0; d < 12; ++d) {
            const float here = oas::glsl::oas_sample(glslPattern, seed, i, d);
            const float there = oas::sample(pattern, seed, i, d);
            ASSERT_EQ(std::memcmp(&here, &there, 4), 0) << "sample " << i << " dim " << d;
            ASSERT_GE(here, 0.0f);
            ASSERT_LT(here, 1.0f);
        }
    }
}

}  // namespace
