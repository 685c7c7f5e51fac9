// oas-merge: adds render files (shards) of one frame, written by oas-render --samples A:B (or any
// oas-render / oas-view render), into one render file plus its PNG preview. The sums are exact
// integers (render/accumulation.hpp), so the result is bit for bit the one-process render of the
// shards' samples, whatever the split and the order of the files.
//
// It refuses, naming the file and the header field, and writes nothing when: a file is not a
// render file (a plain EXR, a truncated one), the shards differ in scene, resolution, sampler,
// plan or seed, two shards hold the same sample, or the union differs from --expect A:B.
//
// Exit status: 0 written; 2 refused or bad arguments; 1 the output could not be written.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#include "apps/cli_main.hpp"
#include "image/image.hpp"
#include "oas/pattern.hpp"
#include "render/render_file.hpp"

int main(int argc, char** argv)
{
    CLI::App app{"oas-merge: add render shards of one frame (oas-render --samples A:B) into one render"};
    std::vector<std::string> inputs;
    std::string output, expect;
    app.add_option("shards", inputs, "render files of one frame (oas-render's EXR output)")->required();
    app.add_option("-o,--output", output, "merged render file (.exr); a PNG preview is written beside it")->required();
    app.add_option("--expect", expect,
                   "A:B: the shards must hold exactly sample indices [A, B) (a gap or an extra sample is an error)");
    return oas::runCli("oas-merge", app, argc, argv, [&] {
        namespace fs = std::filesystem;
        std::vector<oas::render::RenderFile> shards;
        for (const std::string& input : inputs) {
            std::error_code ec;  // an output that does not exist yet is not an input
            if (fs::equivalent(fs::path(input), fs::path(output), ec))
                throw oas::InvalidArgument("--output " + output + " is also the input " + input +
                                           ": write the merge to a new file");
            shards.push_back(oas::render::readRenderFile(input));
        }
        oas::render::RenderFile merged;
        try {
            merged = oas::render::mergeRenders(shards, inputs);
        } catch (const std::overflow_error& e) {
            // Shards whose sums together pass the exact integer range: a refusal, like any other
            // pair of shards that cannot be one frame.
            throw oas::InvalidArgument(e.what());
        }
        if (!expect.empty()) {
            // Any range a frame can have (spp <= kMaxSamples); the comparison below does the rest.
            const oas::render::SampleRange want = oas::render::parseSampleRange(expect, oas::kMaxSamples, "--expect");
            if (!(merged.ranges.size() == 1 && merged.ranges.front() == want))
                throw oas::InvalidArgument("--expect " + expect + ": the shards hold samples " +
                                           oas::render::formatRanges(merged.ranges) + ", not exactly " +
                                           oas::render::formatRanges({want}));
        }
        merged.attributes["oas.writer"] = "oas-merge";
        const std::string png = oas::render::prepareRenderOutput(output, "--output");
        oas::image::writePngPreview(png, oas::render::writeRenderFile(output, merged.sums, merged.ranges, merged.attributes));
        std::cout << "merged " << shards.size() << " shard" << (shards.size() == 1 ? "" : "s") << ": samples "
                  << oas::render::formatRanges(merged.ranges) << " of " << merged.attributes["oas.sppRequested"] << " ("
                  << merged.attributes["oas.spp"] << " per pixel), rejected samples " << merged.attributes["oas.rejectedSamples"]
                  << "\n";
        if (merged.attributes["oas.device"].find(" + ") != std::string::npos)
            std::cout << "note: the shards come from several devices (" << merged.attributes["oas.device"]
                      << "): a valid render of these samples, but devices round floats differently, so not "
                         "bit-identical to a one-device render\n";
        std::cout << "wrote " << output << " and " << png << "\n";
        return 0;
    });
}
