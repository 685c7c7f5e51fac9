#pragma once
// The sampler pattern a scene asks for (its "sampler" object, after any command-line overrides),
// shared by oas-render and oas-view so that both render the same samples for the same request.
#include <cstdint>
#include <string>

#include "oas/pattern.hpp"
#include "render/plan.hpp"
#include "scene/scene.hpp"

namespace oas::render {

struct ScenePattern {
    oas::Pattern pattern;
    std::string choice;  ///< oas::describe(pattern), or the chooser's explanation for "oa"
};

/// makePattern (or, for "oa", chooseOrthogonalArray) for the scene's sampler at plan.sampleDims.
/// Throws oas::InvalidArgument naming the scene file's "sampler" object, and the command-line
/// options when `fromOptions` says they changed it.
ScenePattern scenePattern(const oas::scene::Scene& scene, const DimensionPlan& plan, bool fromOptions);

}  // namespace oas::render
