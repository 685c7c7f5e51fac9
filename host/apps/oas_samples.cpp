// oas-samples: print one pixel's point set of any sampler, so people can look at and check a
// pattern. Values are printed with 9 significant digits, which round-trips every float32 exactly.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "apps/cli_main.hpp"
#include "oas/atomic_file.hpp"
#include "oas/generate_gpu.hpp"
#include "oas/pattern.hpp"
#include "oas/stratification.hpp"

namespace {

std::string toCsv(const std::vector<float>& values, std::uint32_t dims)
{
    std::string out;
    char buf[32];
    for (std::size_t i = 0; i < values.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.9g", double(values[i]));
        out += buf;
        out += (i + 1) % dims == 0 ? '\n' : ',';
    }
    return out;
}

/// NumPy .npy v1.0: little-endian float32 array of shape (points, dims).
std::string toNpy(const std::vector<float>& values, std::uint32_t dims)
{
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(values.size() / dims) + ", " +
                         std::to_string(dims) + "), }";
    const std::size_t preamble = 10;
    while ((preamble + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    std::string out = "\x93NUMPY";
    out += char(1);
    out += char(0);
    out += char(header.size() & 0xff);
    out += char(header.size() >> 8);
    out += header;
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
    return out;
}

/// "X,Y" with plain decimal digits only (no sign, no spaces), each in 0 .. 2^32 - 1.
std::pair<std::uint32_t, std::uint32_t> parsePixel(const std::string& text)
{
    const auto bad = [&] { return oas::InvalidArgument("--pixel '" + text + "' must be X,Y with integers in 0 .. 4294967295"); };
    const auto comma = text.find(',');
    if (comma == std::string::npos) throw bad();
    auto number = [&](const std::string& part) {
        if (part.empty() || part.size() > 10 || part.find_first_not_of("0123456789") != std::string::npos) throw bad();
        const std::uint64_t v = std::stoull(part);
        if (v > 0xffffffffull) throw bad();
        return std::uint32_t(v);
    };
    return {number(text.substr(0, comma)), number(text.substr(comma + 1))};
}

void printList(std::uint32_t spp, std::uint32_t dims, std::uint32_t strength)
{
    std::printf("samplers (valid spp near %u, %u dims%s):\n", spp, dims,
                strength ? (", strength " + std::to_string(strength)).c_str() : "");
    const std::uint32_t lo = spp > 1 ? spp / 2 : 1, hi = spp * 2;
    std::vector<std::string> names = {"oa"};
    for (auto& n : oas::samplerNames()) names.push_back(n);
    for (auto& name : names) {
        auto counts = oas::validCounts(name, strength, dims, lo, hi);
        std::string list;
        for (std::size_t i = 0; i < counts.size() && i < 12; ++i) {
            if (i) list += ' ';
            list += std::to_string(counts[i]);
        }
        if (counts.size() > 12) list += " ...";
        std::printf("  %-20s %s\n  %-20s spp in [%u, %u]: %s\n", name.c_str(), oas::samplerDescription(name).c_str(), "", lo, hi,
                    list.empty() ? "none" : list.c_str());
    }
}

/// The pattern's words by name, in layout order, for hosts that upload it without linking oas.
std::string patternJson(const oas::Pattern& p)
{
    const std::uint32_t* words = &p.construction;
    std::string out = "{\n  \"describe\": \"" + oas::describe(p) + "\",\n  \"words\": [";
    for (int i = 0; i < 16; ++i) out += (i ? ", " : "") + std::to_string(words[i]);
    out += "],\n";
    for (int i = 0; i < 16; ++i)
        out += "  \"" + std::string(oas_pattern_field_name(std::size_t(i))) + "\": " + std::to_string(words[i]) +
               (i < 15 ? ",\n" : "\n");
    return out + "}\n";
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-samples: print one pixel's samples of an orthogonal-array or baseline sampler"};
    oas::PatternRequest request;
    request.spp = 0;
    std::string device = "cpu", format = "csv", pixel = "0,0", output;
    std::uint32_t seed = 0;
    bool list = false, summary = false, explain = false, printPattern = false;
    app.add_option("--sampler", request.sampler, "sampler name, or 'oa' for the best orthogonal array (see --list)");
    app.add_option("--spp", request.spp, "points per pixel")->check(CLI::Range(1u, oas::kMaxSamples));
    app.add_option("--dims", request.dims, "dimensions per point")->check(CLI::Range(1u, oas::kMaxDims));
    app.add_option("--strength", request.strength, "OA strength t (bush, cmjnd, oa); default 2 (cmjnd: dims)");
    app.add_option("--offset", request.offset, "OA offset")->check(CLI::IsMember({"centered", "j", "mj", "cmj"}));
    app.add_option("--seed", seed, "user seed");
    app.add_option("--pixel", pixel, "pixel coordinates X,Y (0 .. 2^32-1)");
    app.add_option("--device", device, "where to generate")->check(CLI::IsMember({"cpu", "gpu"}));
    app.add_option("--format", format, "output format")->check(CLI::IsMember({"csv", "npy"}));
    app.add_option("-o,--output", output, "write the points to this file instead of standard output");
    app.add_flag("--round-up", request.roundUp, "use the next valid spp when spp cannot be made exactly");
    app.add_flag("--list", list, "list samplers and the valid spp near --spp");
    app.add_flag("--summary", summary, "print the pattern's stratification summary to standard error");
    app.add_flag("--explain", explain, "print which pattern was chosen and why, to standard error");
    app.add_flag("--print-pattern", printPattern,
                 "print the 64-byte OasPattern (16 named words, docs/PATTERN.md) as JSON instead of samples");
    // In range, but more than this machine can hold: say how much was asked for.
    const auto outOfMemory = [&] {
        const double values = double(request.spp) * request.dims;
        char text[320];
        std::snprintf(text, sizeof text,
                      "out of memory for --spp %u x --dims %u = %.0f values (%.1f GiB as float32, about %.0f GiB as "
                      "%s text): valid fewer samples or dimensions per call",
                      request.spp, request.dims, values, values * 4 / 1073741824.0,
                      values * (format == "npy" ? 4 : 13) / 1073741824.0, format.c_str());
        return std::string(text);
    };
    return oas::runCli(
        "oas-samples", app, argc, argv,
        [&] {
            if (list) {
                printList(request.spp ? request.spp : 64, request.dims, request.strength);
                return 0;
            }
            if (request.spp == 0) throw oas::InvalidArgument("--spp is required (1 .. 16777216)");
            const auto [px, py] = parsePixel(pixel);
            oas::Pattern pattern;
            std::string chosen = request.sampler;
            if (request.sampler == "oa") {
                const auto choice = oas::chooseOrthogonalArray(request);
                pattern = choice.pattern;
                if (explain || summary) std::cerr << choice.explanation << "\n";
            } else {
                pattern = oas::makePattern(request);
                if (explain || summary) std::cerr << "pattern: " << oas::describe(pattern) << "\n";
            }
            if (pattern.N != request.spp) std::cerr << "note: spp rounded up from " << request.spp << " to " << pattern.N << "\n";
            if (printPattern) {
                const std::string text = patternJson(pattern);
                if (output.empty())
                    std::fwrite(text.data(), 1, text.size(), stdout);
                else
                    oas::writeFileAtomically(output, text);
                return 0;
            }
            oas::SampleRequest sr;
            sr.x0 = px;
            sr.y0 = py;
            sr.spp = pattern.N;
            sr.dims = request.dims;
            sr.seed = seed;
            std::vector<float> values(std::size_t(sr.spp) * sr.dims);
            if (device == "gpu") {
                oas::vk::selectLavapipeIfUnset();
                oas::vk::Context context;
                oas::GpuGenerator generator(context);
                generator.generate(pattern, sr, values.data());
                if (explain || summary) std::cerr << "generated on " << context.deviceName() << "\n";
            } else {
                oas::generateCpu(pattern, sr, values.data(), 1);
            }
            if (summary) {
                const auto s = oas::summarize(pattern, values.data(), sr.spp, sr.dims);
                std::cerr << "stratification of pixel (" << px << "," << py << "), " << sr.spp << " points x " << sr.dims
                          << " dims:\n";
                for (auto& line : s.lines) std::cerr << line << "\n";
            }
            const std::string bytes = format == "npy" ? toNpy(values, sr.dims) : toCsv(values, sr.dims);
            if (output.empty())
                std::fwrite(bytes.data(), 1, bytes.size(), stdout);
            else {
                oas::writeFileAtomically(output, bytes);
                if (summary || explain) std::cerr << "wrote " << output << "\n";
            }
            return 0;
        },
        outOfMemory);
}
