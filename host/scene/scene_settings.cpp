// How the scene is rendered: "integrator" and "sampler".
#include <algorithm>

#include <fmt/format.h>

#include "scene/scene_loader.hpp"

namespace oas::scene::detail {

namespace {

constexpr std::uint32_t kMaxSpp = 1u << 24;
constexpr std::uint32_t kMaxPathDepth = 256;

}  // namespace

Integrator Loader::integrator(const json& v) const
{
    const std::string p = "integrator";
    if (!v.is_object()) typeError(v, p, "an object", "an integrator object");
    Integrator it;
    std::string type = "path";
    if (auto* t = find(v, "type")) type = choice(*t, child(p, "type"), {"direct", "path"});
    if (type == "direct") {
        objectKeys(v, p, "a direct-lighting integrator", {"type", "maxDepth", "nextEventEstimation", "mis"});
        it.type = Integrator::Type::Direct;
        it.maxDepth = 1;
        if (auto* d = find(v, "maxDepth")) it.maxDepth = integer(*d, child(p, "maxDepth"), 1, 1, "1 for direct lighting");
    } else {
        objectKeys(v, p, "a path integrator", {"type", "maxDepth", "nextEventEstimation", "mis", "rouletteStartDepth"});
        it.type = Integrator::Type::Path;
        if (auto* d = find(v, "maxDepth"))
            it.maxDepth = integer(*d, child(p, "maxDepth"), 1, kMaxPathDepth, "1 .. 256 scattering vertices");
        if (auto* r = find(v, "rouletteStartDepth"))
            it.rouletteStartDepth = integer(*r, child(p, "rouletteStartDepth"), 0, it.maxDepth,
                                            fmt::format("0 (never) .. maxDepth = {}", it.maxDepth));
    }
    if (auto* n = find(v, "nextEventEstimation")) it.nextEventEstimation = boolean(*n, child(p, "nextEventEstimation"));
    it.mis = it.nextEventEstimation;
    if (auto* m = find(v, "mis")) {
        it.mis = boolean(*m, child(p, "mis"));
        if (it.mis && !it.nextEventEstimation)
            fail(child(p, "mis"), "true without next-event estimation: valid false when nextEventEstimation is false "
                                  "(MIS weighs light sampling against BSDF sampling)");
    }
    return it;
}

SamplerSpec Loader::sampler(const json& v) const
{
    const std::string p = "sampler";
    objectKeys(v, p, "the sampler", {"name", "spp", "offset", "strength", "seed"});
    SamplerSpec spec;
    if (auto* n = find(v, "name")) {
        spec.name = string(*n, child(p, "name"));
        const auto& names = samplerNames();
        if (std::find(names.begin(), names.end(), spec.name) == names.end())
            fail(child(p, "name"), fmt::format("\"{}\" is not a sampler: valid {}", spec.name, join(names, " | ")));
    }
    spec.spp = integer(require(v, p, "spp", "1 .. 16777216 samples per pixel"), child(p, "spp"), 1, kMaxSpp,
                       "1 .. 16777216 (2^24) samples per pixel");
    const bool oa = samplerIsOrthogonalArray(spec.name);
    if (auto* o = find(v, "offset")) {
        if (!oa)
            fail(child(p, "offset"), fmt::format("{} given for sampler \"{}\", which is not an orthogonal array: "
                                                 "valid only with oa, bose, bush, bose-bush, addelman-kempthorne, cmjnd",
                                                 show(*o), spec.name));
        spec.offset = choice(*o, child(p, "offset"), {"centered", "j", "mj", "cmj"});
    }
    if (auto* s = find(v, "strength")) {
        if (!oa)
            fail(child(p, "strength"), fmt::format("{} given for sampler \"{}\", which is not an orthogonal array: "
                                                   "valid only with oa, bose, bush, bose-bush, addelman-kempthorne, cmjnd",
                                                   show(*s), spec.name));
        const bool twoOnly = spec.name == "bose" || spec.name == "bose-bush" || spec.name == "addelman-kempthorne";
        spec.strength =
            twoOnly ? integer(*s, child(p, "strength"), 0, 2, fmt::format("0 (default) or 2: {} has strength 2 only", spec.name))
                    : integer(*s, child(p, "strength"), 0, 24, "0 (the sampler's default) or 2 .. 24");
        if (spec.strength == 1) fail(child(p, "strength"), "1 is out of range: valid 0 (the sampler's default) or 2 .. 24");
    }
    if (auto* s = find(v, "seed")) spec.seed = integer(*s, child(p, "seed"), 0, 0xffffffffu, "0 .. 4294967295");
    return spec;
}

}  // namespace oas::scene::detail
