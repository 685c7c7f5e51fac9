#version 450
// Smoke test for the Vulkan host layer: exercises a storage buffer binding and push constants.
layout(local_size_x = 64) in;

layout(push_constant) uniform Push {
  uint n;
  uint add;
} pc;

layout(std430, binding = 0) buffer Data {
  uint data[];
};

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.n) data[i] = i * 3u + pc.add;
}
