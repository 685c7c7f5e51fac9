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

/// The rows of the first markdown table after `heading` in `text`, cells trimmed.
std::vector<std::vector<std::string>> tableAfter(const std::string& text, const std::string& heading)
{
    std::vector<std::vector<std::string>> rows;
    const std::size_t at = text.find(heading);
    if (at == std::string::npos) return rows;  // the callers' size checks then fail, naming the file
    std::istringstream in(text.substr(at));
    bool inTable = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("|", 0) != 0) {
            if (inTable) break;
            continue;
        }
        inTable = true;
        if (line.find("---") != std::string::npos) continue;
        std::vector<std::string> cells;
        std::istringstream cellsIn(line.substr(1));
        for (std::string cell; std::getline(cellsIn, cell, '|');) {
            const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
            cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
        }
        rows.push_back(cells);
    }
    return rows;
}

TEST(Readme, TheAnswerTableIsStudysShortAnswer)
{
    // README's "Which sampler, at what cost" table is docs/STUDY.md's short answer, copied by hand
    // with the budgets' notes left out and the "timed on" column cut to the device ("lavapipe" for
    // llvmpipe, "CPU twin"; the text above it names the machine and date): every scene, budget,
    // device, verdict and ratio must be the same.
    const std::string root = OAS_SOURCE_DIR;
    const auto readme = tableAfter(readFile(root + "/README.md"), "## Which sampler, at what cost");
    const auto study = tableAfter(readFile(root + "/docs/STUDY.md"), "## The short answer");
    ASSERT_GE(study.size(), 2u) << "docs/STUDY.md has no short-answer table";
    ASSERT_EQ(readme.size(), study.size()) << "README's answer table and STUDY.md's differ in their rows";
    auto shorten = [](std::string cell) {
        for (const std::string note : {" (Sobol's 128 spp)", " (≈ 4096 spp)"})
            if (const auto at = cell.find(note); at != std::string::npos) cell.erase(at, note.size());
        const std::string at = " at ≈ ";
        if (const auto where = cell.find(at); where != std::string::npos) cell.replace(where, at.size(), " ≈ ");
        return cell;
    };
    auto device = [](const std::string& timedOn) {
        if (timedOn.rfind("CPU twin", 0) == 0) return std::string("CPU twin");
        if (timedOn.rfind("llvmpipe", 0) == 0) return std::string("lavapipe");
        return timedOn.substr(0, timedOn.find(", "));
    };
    for (std::size_t r = 1; r < study.size(); ++r) {
        ASSERT_EQ(study[r].size(), 7u) << "STUDY.md row " << r;
        ASSERT_EQ(readme[r].size(), 7u) << "README row " << r;
        for (std::size_t c = 0; c < 6; ++c)
            EXPECT_EQ(readme[r][c], shorten(study[r][c])) << "README's answer table, row " << r << ", column " << c + 1;
        EXPECT_EQ(readme[r][6], device(study[r][6])) << "README's answer table, row " << r << ": the device";
    }
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
