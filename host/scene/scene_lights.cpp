// "lights": point and spot lights (area lights are emitting shapes, scene_shapes.cpp).
#include <cfloat>
#include <cmath>

#include <fmt/format.h>

#include "scene/scene_loader.hpp"

namespace oas::scene::detail {

void Loader::lights(const json& v, Scene& scene) const
{
    forEachObject(v, "lights", "light", [&](const json& l, const std::string& p) {
        const std::string type = choice(require(l, p, "type", "point | spot"), child(p, "type"), {"point", "spot"},
                                        " (area lights are shapes whose material has \"emission\"; a constant environment is the "
                                        "top-level \"environment\")");
        Light light;
        if (type == "point") {
            objectKeys(l, p, "a point light", {"type", "position", "intensity"});
            light.type = Light::Type::Point;
        } else {
            objectKeys(l, p, "a spot light", {"type", "position", "intensity", "direction", "outerAngle", "innerAngle"});
            light.type = Light::Type::Spot;
        }
        light.position = vec3(require(l, p, "position", "[x, y, z]"), child(p, "position"));
        light.intensity =
            color(require(l, p, "intensity", "W/sr, a number or [r, g, b] >= 0"), child(p, "intensity"), 0, FLT_MAX);
        if (light.type == Light::Type::Spot) {
            light.direction =
                unitVector(nonzeroVec3(require(l, p, "direction", "[x, y, z], nonzero"), child(p, "direction"), "direction"));
            const float outer = realIn(require(l, p, "outerAngle", "degrees in (0, 180]"), child(p, "outerAngle"), 0, 180,
                                       "(0, 180] degrees (half-angle from the axis)", true);
            float inner = outer;
            if (auto* in = find(l, "innerAngle"))
                inner = realIn(*in, child(p, "innerAngle"), 0, outer,
                               fmt::format("0 .. outerAngle = {} degrees (half-angle from the axis)", outer));
            constexpr double kDegree = 3.14159265358979323846 / 180.0;
            light.cosOuter = float(std::cos(double(outer) * kDegree));
            light.cosInner = float(std::cos(double(inner) * kDegree));
        }
        scene.lights.push_back(light);
    });
}

}  // namespace oas::scene::detail
