#include "render/scene_pattern.hpp"

namespace oas::render {

ScenePattern scenePattern(const oas::scene::Scene& scene, const DimensionPlan& plan, bool fromOptions)
{
    oas::PatternRequest request;
    request.sampler = scene.sampler.name;
    request.spp = scene.sampler.spp;
    request.dims = plan.sampleDims;
    request.strength = scene.sampler.strength;
    request.offset = scene.sampler.offset;
    try {
        ScenePattern out;
        if (request.sampler == "oa") {
            const auto c = oas::chooseOrthogonalArray(request);
            out.pattern = c.pattern;
            out.choice = c.explanation;
        } else {
            out.pattern = oas::makePattern(request);
            out.choice = oas::describe(out.pattern);
        }
        return out;
    } catch (const oas::InvalidArgument& e) {
        // Name where the request came from: the scene's "sampler" object or the options.
        throw oas::InvalidArgument(scene.path.string() + ": sampler" +
                                   (fromOptions ? " (with the --sampler/--spp/--offset/--strength options)" : "") +
                                   ": " + e.what());
    }
}

std::map<std::string, std::string> renderAttributes(const oas::scene::Scene& scene, const DimensionPlan& plan,
                                                    const oas::Pattern& pattern, std::uint32_t sppDone)
{
    std::string planLine = plan.explain();
    planLine = planLine.substr(0, planLine.find('\n'));
    return {{"oas.spp", std::to_string(sppDone)},
            {"oas.sppRequested", std::to_string(scene.sampler.spp)},
            {"oas.sampler", oas::describe(pattern)},
            {"oas.dimensionPlan", planLine},
            {"oas.scene", scene.path.string()}};
}

}  // namespace oas::render
