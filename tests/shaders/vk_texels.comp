#version 450
// Smoke test for texel-buffer bindings: copies every uvec4 texel of binding 0 (a uniform texel
// buffer, R32G32B32A32_UINT) into the storage buffer at binding 1, word for word.
layout(local_size_x = 64) in;

layout(push_constant) uniform Push {
  uint texels;
} pc;

layout(binding = 0) uniform usamplerBuffer source;
layout(std430, binding = 1) buffer Copy {
  uvec4 copy[];
};

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.texels) copy[i] = texelFetch(source, int(i));
}
