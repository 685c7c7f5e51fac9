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
                                   (fromOptions ? " (with the --sampler/--spp/--offset/--strength options)" : "") + ": " +
                                   e.what());
    }
}

}  // namespace oas::render
