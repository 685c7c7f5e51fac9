#pragma once
// The path tracer's GPU data structs (shaders/pt/pt_types.glsl) compiled as C++ with GLM: the
// host fills exactly the structs the shader reads.
#include <glm/glm.hpp>

namespace oas::pt {
using glm::vec4;
#include "pt/pt_types.glsl"
static_assert(sizeof(PtShape) == 80 && sizeof(PtMaterial) == 48 && sizeof(PtLight) == 64 && sizeof(PtNode) == 32 &&
              sizeof(PtGlobals) == 112);
}  // namespace oas::pt
