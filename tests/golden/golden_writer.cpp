// Writes tests/golden/patterns.json to standard output: for each request in golden_cases.hpp, the
// 16 pattern words and some samples as integers F (value = F / 2^24, exact). Run it only when the
// samples change on purpose (then bump the minor version: docs/PATTERN.md), and review the diff:
//   build/tests/oas-golden-writer > tests/golden/patterns.json
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "golden/golden_cases.hpp"
#include "oas/pattern.hpp"

int main()
{
    using json = nlohmann::ordered_json;  // keys in the order written: request first, samples last
    json cases = json::array();
    const std::uint32_t seed = oas::pixelSeed(oas::golden::kPixelX, oas::golden::kPixelY, oas::golden::kSeed);
    for (const auto& c : oas::golden::cases()) {
        oas::PatternRequest request;
        request.sampler = c.sampler;
        request.spp = c.spp;
        request.strength = c.strength;
        request.offset = c.offset;
        request.dims = c.dims;
        const oas::Pattern p = oas::makePattern(request);
        const std::uint32_t* words = &p.construction;
        json samples = json::array();
        const auto indices = oas::golden::indicesFor(p.N);
        const auto dims = oas::golden::dimsFor(p.blockDims);
        for (auto i : indices) {
            json row = json::array();
            for (auto d : dims) row.push_back(std::uint32_t(std::ldexp(double(oas::sample(p, seed, i, d)), 24)));
            samples.push_back(row);
        }
        cases.push_back(
            {{"request",
              {{"sampler", c.sampler}, {"spp", c.spp}, {"strength", c.strength}, {"offset", c.offset}, {"dims", c.dims}}},
             {"describe", oas::describe(p)},
             {"words", std::vector<std::uint32_t>(words, words + 16)},
             {"indices", indices},
             {"dims", dims},
             {"F", samples}});
    }
    // One case per line: short enough to read, and a changed sample shows as a changed line.
    std::printf("{\n \"format\": \"oas golden vectors 1\",\n");
    std::printf(" \"about\": %s,\n",
                json("Requests -> OasPattern words (docs/PATTERN.md, in order) -> samples of one pixel as integers F, "
                     "value = F / 2^24, at the listed sample indices (rows) and dimensions (columns). C "
                     "(oas_make_pattern(words[0], words[2], words[4], words[1])), C++ and GLSL are checked against "
                     "this file by ctest; other ports can check themselves against it.")
                    .dump()
                    .c_str());
    std::printf(
        " \"pixel\": %s,\n",
        json({{"x", oas::golden::kPixelX}, {"y", oas::golden::kPixelY}, {"seed", oas::golden::kSeed}, {"pixelSeed", seed}})
            .dump()
            .c_str());
    std::printf(" \"cases\": [\n");
    for (std::size_t i = 0; i < cases.size(); ++i)
        std::printf("  %s%s\n", cases[i].dump().c_str(), i + 1 < cases.size() ? "," : "");
    std::printf(" ]\n}\n");
}
