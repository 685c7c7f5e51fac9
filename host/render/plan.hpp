#pragma once
// The dimension plan: which sample dimensions a scene's integrand really has, in which order, and
// where each lands. Only effects the scene calls for consume dimensions: the lens only with a
// nonzero aperture, time only when something moves during an open shutter, light selection only
// with more than one light, light positions only with area lights, BSDF directions only where a
// path continues (or MIS needs them), the lobe choice only with dielectrics, roulette only when
// enabled. 2D effects start on even dimensions, so they land on OA partner columns (Bose CMJ
// pairs (0,1), (2,3), ...) in the first block, and in every block where blockDims is even. With
// an odd blockDims (Bose over GF(2^k), Bose-Bush, Addelman-Kempthorne) a later block's pairs
// start at odd dimensions (oas_pair_dimension), which this pattern-independent plan does not
// follow yet: there a 2D effect may straddle two blocks. The GPU kernel and the CPU reference
// both follow this one plan.
#include <cstdint>
#include <string>
#include <vector>

#include "render/pt_constants.hpp"
#include "scene/scene.hpp"

namespace oas::render {

// kAbsent, a dimension the plan does not have, is render/pt_constants.hpp's (the shaders' PT_ABSENT).
/// Most dimensions of one group (the camera's, or one path vertex's): PT_GROUP_MAX in
/// shaders/pt/pt_sample_dims.glsl, whose pt_group_dims fetches a group at a time.
constexpr std::uint32_t kMaxGroupDims = 8;

struct DimensionPlan {
    struct Entry {
        std::string name;     ///< "pixel.xy", "lens.uv", "time", "v1.light.uv", ...
        std::uint32_t first;  ///< first sample dimension
        std::uint32_t count;  ///< 1 or 2
    };
    std::vector<Entry> entries;    ///< every dimension the integrand uses, in order
    std::uint32_t usedDims = 0;    ///< the integrand's dimension: sum of counts
    std::uint32_t sampleDims = 0;  ///< dimensions the sampler must provide (incl. alignment gaps)

    // Layout read by the shaders (pt/pt_sample_dims.glsl, pt_light.glsl, pt_integrator.glsl): camera
    // dims, then one group per path vertex.
    bool hasLens = false, hasMotion = false, hasDielectric = false;
    bool nee = true, mis = true;
    std::uint32_t maxDepth = 1, rouletteStart = 0;
    std::uint32_t pixel = 0, lens = kAbsent, time = kAbsent;
    std::uint32_t vertexBase = 0, vertexStride = 0;
    std::uint32_t lightSelect = kAbsent, lightUV = kAbsent, bsdfUV = kAbsent, lobe = kAbsent, roulette = kAbsent;

    /// "7D: pixel.xy lens.uv time v1.light.uv", then one line per entry with its dimensions.
    std::string explain() const;
};

/// The plan for a scene (its effects, lights, materials and integrator).
DimensionPlan planDimensions(const scene::Scene& scene);

}  // namespace oas::render
