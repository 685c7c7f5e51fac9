#include "render/plan.hpp"

#include <stdexcept>

#include <algorithm>
#include <sstream>

namespace oas::render {

DimensionPlan planDimensions(const scene::Scene& scene)
{
    DimensionPlan plan;
    const auto& integrator = scene.integrator;
    const bool direct = integrator.type == scene::Integrator::Type::Direct;
    plan.maxDepth = direct ? 1 : std::max<std::uint32_t>(integrator.maxDepth, 1);
    plan.nee = integrator.nextEventEstimation && (!scene.lights.empty() || scene.areaLightCount() > 0);
    plan.mis = plan.nee && integrator.mis && scene.areaLightCount() > 0;
    plan.hasLens = scene.hasDepthOfField();
    plan.hasMotion = scene.hasMotionBlur();
    for (const auto& m : scene.materials) plan.hasDielectric = plan.hasDielectric || m.type == scene::Material::Type::Dielectric;
    plan.rouletteStart = direct ? 0 : integrator.rouletteStartDepth;

    // Camera group: 2D effects first (each on an even pair), then 1D ones.
    std::uint32_t next = 0;
    plan.pixel = next;
    next += 2;
    if (plan.hasLens) {
        plan.lens = next;
        next += 2;
    }
    if (plan.hasMotion) plan.time = next++;
    plan.vertexBase = (next + 1) & ~1u;  // vertex groups start on an even dimension

    // Vertex group layout (the same for every vertex): light.uv, bsdf.uv, then 1D effects.
    const std::size_t lightCount = scene.lights.size() + scene.areaLightCount();
    const bool bsdfAnywhere = plan.maxDepth > 1 || plan.mis;
    std::uint32_t offset = 0;
    if (plan.nee && scene.areaLightCount() > 0) {
        plan.lightUV = offset;
        offset += 2;
    }
    if (bsdfAnywhere) {
        plan.bsdfUV = offset;
        offset += 2;
    }
    if (plan.nee && lightCount > 1) plan.lightSelect = offset++;
    if (plan.hasDielectric && bsdfAnywhere) plan.lobe = offset++;
    if (plan.rouletteStart != 0 && plan.rouletteStart < plan.maxDepth) plan.roulette = offset++;
    plan.vertexStride = (offset + 1) & ~1u;
    if (plan.vertexBase > kMaxGroupDims || plan.vertexStride > kMaxGroupDims)
        throw std::logic_error("planDimensions: a dimension group exceeds kMaxGroupDims (pt_sample_dims.glsl PT_GROUP_MAX)");

    auto add = [&](const std::string& name, std::uint32_t first, std::uint32_t count) {
        plan.entries.push_back({name, first, count});
        plan.usedDims += count;
        plan.sampleDims = std::max(plan.sampleDims, first + count);
    };
    add("pixel.xy", plan.pixel, 2);
    if (plan.hasLens) add("lens.uv", plan.lens, 2);
    if (plan.hasMotion) add("time", plan.time, 1);
    for (std::uint32_t v = 1; v <= plan.maxDepth; ++v) {
        const std::uint32_t base = plan.vertexBase + (v - 1) * plan.vertexStride;
        std::string prefix;
        if (plan.maxDepth > 1) {
            prefix = "v";
            prefix += std::to_string(v);
            prefix += '.';
        }
        // Must match pt_radiance: the path stops at the last vertex unless MIS needs a BSDF sample.
        const bool bsdfHere = plan.bsdfUV != kAbsent && (v < plan.maxDepth || plan.mis);
        if (plan.lightSelect != kAbsent) add(prefix + "light.select", base + plan.lightSelect, 1);
        if (plan.lightUV != kAbsent) add(prefix + "light.uv", base + plan.lightUV, 2);
        if (bsdfHere) add(prefix + "bsdf.uv", base + plan.bsdfUV, 2);
        if (bsdfHere && plan.lobe != kAbsent) add(prefix + "bsdf.lobe", base + plan.lobe, 1);
        if (plan.roulette != kAbsent && v >= plan.rouletteStart && v < plan.maxDepth)
            add(prefix + "roulette", base + plan.roulette, 1);
    }
    return plan;
}

std::string DimensionPlan::explain() const
{
    std::ostringstream out;
    out << usedDims << "D:";
    for (const auto& e : entries) out << ' ' << e.name;
    out << "\n  " << sampleDims << " sample dimensions";
    if (sampleDims > usedDims) out << " (" << sampleDims - usedDims << " left empty so 2D effects sit on partner pairs)";
    out << "\n";
    for (const auto& e : entries) {
        out << "  " << e.name << ": dim " << e.first;
        if (e.count == 2) out << "," << e.first + 1;
        out << "\n";
    }
    return out.str();
}

}  // namespace oas::render
