// The embedding snippets must be the code the consumer tests build: every line of every code block
// in the README's "Use it in your renderer" section and in docs/EMBEDDING.md appears, as a whole
// line, in one of the files those tests compile (examples/, tests/c/pattern_c_test.c). Whole-line
// CMake comments are exempt: the docs explain with them. A snippet that drifts from the tested code
// fails here.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#ifndef OAS_SOURCE_DIR
#error "define OAS_SOURCE_DIR"
#endif

namespace {

std::string readFile(const std::string& path)
{
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<std::string> lines(const std::string& text)
{
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
        out.push_back(line);
    }
    return out;
}

struct Block {
    std::string language;
    int firstLine = 0;
    std::vector<std::string> lines;
};

std::vector<Block> snippetsOf(const std::string& readme, const std::string& section)
{
    std::vector<Block> blocks;
    bool inSection = false, inBlock = false;
    int number = 0;
    for (const auto& line : lines(readme)) {
        ++number;
        if (section.empty())
            inSection = true;
        else if (!inBlock && line.rfind("## ", 0) == 0)
            inSection = line == section;
        if (!inSection) continue;
        if (line.rfind("```", 0) == 0) {
            if (inBlock) {
                inBlock = false;
            } else {
                inBlock = true;
                blocks.push_back({line.substr(3), number + 1, {}});
            }
        } else if (inBlock) {
            blocks.back().lines.push_back(line);
        }
    }
    return blocks;
}

std::set<std::string> testedLines()
{
    const std::string root = OAS_SOURCE_DIR;
    std::set<std::string> tested;
    for (const char* file :
         {"/examples/consumer-find-package/CMakeLists.txt", "/examples/consumer-add-subdirectory/CMakeLists.txt",
          "/examples/consumer-fetchcontent/CMakeLists.txt", "/examples/common/consumer.cmake", "/examples/common/consumer.comp",
          "/examples/common/consumer.cpp", "/tests/c/pattern_c_test.c",
          "/tests/shaders/specialized_consumer.comp", "/examples/smallpt/prefetch.comp"}) {
        const auto fileLines = lines(readFile(root + file));
        EXPECT_FALSE(fileLines.empty()) << file;
        tested.insert(fileLines.begin(), fileLines.end());
    }
    return tested;
}

// Checks every snippet line of `blocks` (from `file`) against the tested files; returns the languages seen.
std::set<std::string> expectSnippetsAreTested(const std::vector<Block>& blocks, const std::string& file)
{
    const std::set<std::string> tested = testedLines();
    std::set<std::string> languages;
    for (const auto& block : blocks) {
        languages.insert(block.language);
        for (std::size_t i = 0; i < block.lines.size(); ++i) {
            const std::string& line = block.lines[i];
            if (line.empty()) continue;
            if (block.language == "cmake" && line.rfind("# ", 0) == 0) continue;
            EXPECT_TRUE(tested.count(line)) << file << ":" << block.firstLine + i << " is not in the tested examples:\n" << line;
        }
    }
    return languages;
}

TEST(Readme, UseItInYourRendererShowsTheTestedCode)
{
    const std::vector<Block> blocks =
        snippetsOf(readFile(std::string(OAS_SOURCE_DIR) + "/README.md"), "## Use it in your renderer");
    ASSERT_GE(blocks.size(), 3u) << "the section or its code blocks are missing";
    EXPECT_EQ(expectSnippetsAreTested(blocks, "README.md"), (std::set<std::string>{"cmake", "glsl", "c"}));
}

TEST(Readme, EmbeddingGuideShowsTheTestedCode)
{
    const std::vector<Block> blocks = snippetsOf(readFile(std::string(OAS_SOURCE_DIR) + "/docs/EMBEDDING.md"), "");
    ASSERT_GE(blocks.size(), 7u) << "docs/EMBEDDING.md or its code blocks are missing";
    EXPECT_EQ(expectSnippetsAreTested(blocks, "docs/EMBEDDING.md"), (std::set<std::string>{"cmake", "glsl", "c", "cpp"}));
}

TEST(Readme, TheCheckCatchesADriftedLine)
{
    // Negative control: a snippet line that is not in a tested file is found.
    const auto blocks =
        snippetsOf("## Use it in your renderer\n```cmake\nfind_package(oas 9.9 REQUIRED)\n```\n## Next\n```c\nx\n```\n",
                   "## Use it in your renderer");
    ASSERT_EQ(blocks.size(), 1u);
    EXPECT_EQ(blocks[0].lines, std::vector<std::string>{"find_package(oas 9.9 REQUIRED)"});
}

}  // namespace
