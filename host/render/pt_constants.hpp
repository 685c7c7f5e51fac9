#pragma once
// The path tracer's table of specialization constants and buffer bindings (shaders/pt/
// pt_constants.glsl) compiled as C++: the host reads the very entries the shaders declare.
#include <cstdint>

namespace oas::pt {
using uint = std::uint32_t;
#include "pt/pt_constants.glsl"

/// The kernel's specialization constants, one field per table entry (named after it, of its
/// type), each initialised to the table's default. specialization() (render/tracer.hpp) sets the
/// fields from their table HOST expressions; the GPU tracer passes every field as its constant_id,
/// the CPU tracer reads the plan's.
struct PtSpecialization {
#define PT_SPECIALIZATION_FIELD(NAME, ID, TYPE, DEFAULT, HOST) TYPE NAME = DEFAULT;
    PT_SPEC_CONSTANTS(PT_SPECIALIZATION_FIELD)
#undef PT_SPECIALIZATION_FIELD
};
}  // namespace oas::pt

namespace oas::render {

/// "Absent" (pt_constants.glsl's PT_ABSENT): a dimension the plan does not have.
constexpr std::uint32_t kAbsent = pt::PT_ABSENT;

/// Buffers of pt_render.comp: bindings 0 .. kBindingCount - 1 (pt_constants.glsl's PT_BINDINGS).
#define PT_COUNT_BINDING(NAME, BINDING, TEXELS) +1
constexpr std::uint32_t kBindingCount = 0 PT_BINDINGS(PT_COUNT_BINDING);
#undef PT_COUNT_BINDING

}  // namespace oas::render
