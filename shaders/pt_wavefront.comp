#version 450
// The path tracer as a wavefront (Laine, Karras and Aila, "Megakernels Considered Harmful:
// Wavefront Path Tracing on GPUs", HPG 2013): the paths of a batch live in memory as records
// (PtPath, pt/pt_integrator.glsl), and each dispatch advances every live path by one vertex, so
// a lane is never held by a longer path of its group, as in the megakernel (pt_render.comp),
// where a group of lanes runs until its longest path ends. Four kernels, chosen by the
// specialization constant PT_WAVEFRONT_STAGE (host/render/wavefront_gpu.cpp dispatches them):
//   0 camera   one invocation per (pixel, sample) of the batch: the camera ray's path record,
//              written at its own index (every camera path is live)
//   1 step     one invocation per live path of the input queue: pt_path_step, the one step the
//              megakernel and the C++ twin loop over; a path that lives on is appended to the
//              output queue (an atomic counter), one that ends writes its radiance to its slot
//   2 resolve  one invocation per pixel: the batch's radiances of that pixel, in sample order,
//              added to the exact sums as the megakernel adds them
//   3 size     one invocation before each step: the step's live paths (the camera's, or those
//              the step before appended) and its group counts, which the step's dispatch reads
//              on the device (vkCmdDispatchIndirect): a batch's kernels are one command buffer,
//              with no round trip through the host between steps
// Records are compacted themselves, in queue order, and each invocation reads the record at its
// own index (lavapipe fetches a texel for all lanes at once and loads a storage-buffer element
// one lane at a time: host/vk/context.hpp). The sums are integers, so the words equal the
// megakernel's whatever order the paths end in (tests/wavefront_test.cpp).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

#include "pt/pt_kernel.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform WavefrontParams {
    OasPattern pattern;
    uint tileX;
    uint tileY;
    uint tileWidth;
    uint tileHeight;
    uint firstSample;
    uint sampleCount;
    uint seed;
    uint pathCount;  ///< camera, size: the paths the batch starts
    uint vertex;     ///< step, size: the vertex the input queue's paths find (1 .. PT_MAX_DEPTH + 1)
} params;

OasPattern pt_pattern() { return params.pattern; }

#include "pt/pt_trace.glsl"

/// A path record: PtPath's fields as 32-bit words, then the path's slot (pixel of the tile x
/// sampleCount + sample of the batch), which names its pixel, its sample and where its radiance
/// goes. Five texels of uvec4.
const uint PT_PATH_WORDS = 20u;
/// Words per slot of the results: the radiance's three channels and a spare (whole texels).
const uint PT_RESULT_WORDS = 4u;

layout(binding = PT_BINDING_PATHS_IN) uniform usamplerBuffer pathsIn;
layout(binding = PT_BINDING_PATHS_OUT, r32ui) uniform writeonly uimageBuffer pathsOut;
layout(binding = PT_BINDING_RESULTS, r32ui) uniform uimageBuffer results;
/// The counters' words (host/render/wavefront_gpu.cpp reads them after the batch and checks that
/// every path started ends once): records the step appended to its output queue; paths ended; the
/// next step's group counts (three words, read by its indirect dispatch); its live paths; and
/// from PT_COUNTER_STEPPED on, the live paths of each step by vertex.
const uint PT_COUNTER_APPENDED = 0u;
const uint PT_COUNTER_FINISHED = 1u;
const uint PT_COUNTER_GROUPS = 2u;
const uint PT_COUNTER_LIVE = 5u;
const uint PT_COUNTER_STEPPED = 8u;
/// Groups along x of an indirect dispatch: Vulkan's least maxComputeWorkGroupCount, any device's.
const uint PT_MAX_GROUPS_X = 65535u;
layout(std430, binding = PT_BINDING_COUNTERS) buffer Counters { uint counters[]; };

uint pt_invocation() { return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x; }

void pt_store_path(uint at, PtPath p, uint slot)
{
    uint w[PT_PATH_WORDS] = uint[PT_PATH_WORDS](
        floatBitsToUint(p.origin.x), floatBitsToUint(p.origin.y), floatBitsToUint(p.origin.z), floatBitsToUint(p.dir.x),
        floatBitsToUint(p.dir.y), floatBitsToUint(p.dir.z), floatBitsToUint(p.radiance.x), floatBitsToUint(p.radiance.y),
        floatBitsToUint(p.radiance.z), floatBitsToUint(p.throughput.x), floatBitsToUint(p.throughput.y),
        floatBitsToUint(p.throughput.z), floatBitsToUint(p.lastPosition.x), floatBitsToUint(p.lastPosition.y),
        floatBitsToUint(p.lastPosition.z), floatBitsToUint(p.time), floatBitsToUint(p.lastPdf), p.vertex, p.lastSpecular, slot);
    [[unroll]] for (uint k = 0u; k < PT_PATH_WORDS; ++k) imageStore(pathsOut, int(at * PT_PATH_WORDS + k), uvec4(w[k]));
}

/// The record at `at` of the input queue, with its slot in the `alive` field (a queued path is
/// live, so the record keeps its slot there; the caller takes it and sets the flag).
PtPath pt_load_path(uint at)
{
    uvec4 t0 = texelFetch(pathsIn, int(at * 5u));
    uvec4 t1 = texelFetch(pathsIn, int(at * 5u + 1u));
    uvec4 t2 = texelFetch(pathsIn, int(at * 5u + 2u));
    uvec4 t3 = texelFetch(pathsIn, int(at * 5u + 3u));
    uvec4 t4 = texelFetch(pathsIn, int(at * 5u + 4u));
    PtPath p;
    p.origin = uintBitsToFloat(uvec3(t0.x, t0.y, t0.z));
    p.dir = uintBitsToFloat(uvec3(t0.w, t1.x, t1.y));
    p.radiance = uintBitsToFloat(uvec3(t1.z, t1.w, t2.x));
    p.throughput = uintBitsToFloat(uvec3(t2.y, t2.z, t2.w));
    p.lastPosition = uintBitsToFloat(uvec3(t3.x, t3.y, t3.z));
    p.time = uintBitsToFloat(t3.w);
    p.lastPdf = uintBitsToFloat(t4.x);
    p.vertex = t4.y;
    p.lastSpecular = t4.z;
    p.alive = t4.w;  // the slot, until the caller takes it
    return p;
}

/// A slot's pixel (px, py) and the sample's seed and index.
struct PtSlot {
    uint px;
    uint py;
    PtSampleState st;
};
PtSlot pt_slot(uint slot)
{
    uint pixel = slot / params.sampleCount;
    uint row = pixel / params.tileWidth;
    PtSlot s;
    s.px = params.tileX + (pixel - row * params.tileWidth);
    s.py = params.tileY + row;
    s.st.seed = oas_pixel_seed(s.px, s.py, params.seed);
    s.st.index = params.firstSample + (slot - pixel * params.sampleCount);
    return s;
}

/// A group of the slot's sample: from the prefetched samples (laid out [pixel][sample][dim], so
/// the slot is the sample's place), or oas_draw. The same bits either way.
OasDraw pt_slot_group(uint slot, PtSampleState st, uint first, uint count)
{
    if (PT_PREFETCH_DIMS == 0u) return oas_draw(params.pattern, st.seed, st.index, first, count);
    return pt_prefetched_group(slot * (PT_PREFETCH_DIMS / 4u), first, count);
}

void main()
{
    uint i = pt_invocation();
    if (PT_WAVEFRONT_STAGE == 0u) {
        if (i >= params.pathCount) return;
        PtSlot s = pt_slot(i);
        OasDraw d = pt_slot_group(i, s.st, 0u, pt_camera_dims_used());
        pt_store_path(i, pt_path_begin(s.px, s.py, d, pt_globals()), i);
    } else if (PT_WAVEFRONT_STAGE == 3u) {
        if (i != 0u) return;
        uint live = params.vertex == 1u ? params.pathCount : counters[PT_COUNTER_APPENDED];
        counters[PT_COUNTER_LIVE] = live;
        counters[PT_COUNTER_STEPPED + params.vertex] = live;
        counters[PT_COUNTER_APPENDED] = 0u;
        uint groups = (live + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
        uint gx = min(groups, PT_MAX_GROUPS_X);
        counters[PT_COUNTER_GROUPS] = gx;
        counters[PT_COUNTER_GROUPS + 1u] = gx == 0u ? 0u : (groups + gx - 1u) / gx;
        counters[PT_COUNTER_GROUPS + 2u] = 1u;
    } else if (PT_WAVEFRONT_STAGE == 1u) {
        if (i >= counters[PT_COUNTER_LIVE]) return;
        PtPath p = pt_load_path(i);
        uint slot = p.alive;
        p.alive = 1u;
        PtSlot s = pt_slot(slot);
        uint v = params.vertex;
        OasDraw d = pt_slot_group(slot, s.st, pt_vertex_dim(v, 0u), v > PT_MAX_DEPTH ? 0u : pt_vertex_dims_used());
        p = pt_path_step(p, d, pt_globals());
        if (p.alive != 0u) {
            pt_store_path(atomicAdd(counters[PT_COUNTER_APPENDED], 1u), p, slot);
        } else {
            [[unroll]] for (uint c = 0u; c < 3u; ++c)
                imageStore(results, int(slot * PT_RESULT_WORDS + c), uvec4(floatBitsToUint(p.radiance[c])));
            atomicAdd(counters[PT_COUNTER_FINISHED], 1u);
        }
    } else {
        // A batch that lost a path (or ended one twice) leaves the sums as they were: the host
        // reads the counters after the batch and throws, and no stale radiance gets in meanwhile.
        if (counters[PT_COUNTER_FINISHED] != params.pathCount) return;
        if (i >= params.tileWidth * params.tileHeight) return;
        uint row = i / params.tileWidth;
        uint px = params.tileX + (i - row * params.tileWidth);
        uint py = params.tileY + row;
        PtSum sum = pt_sum_zero();
        uint rejected = 0u;
        for (uint k = 0u; k < params.sampleCount; ++k) {
            uint slot = i * params.sampleCount + k;
            vec3 l = uintBitsToFloat(uvec3(imageLoad(results, int(slot * PT_RESULT_WORDS)).x,
                                           imageLoad(results, int(slot * PT_RESULT_WORDS + 1u)).x,
                                           imageLoad(results, int(slot * PT_RESULT_WORDS + 2u)).x));
            if (pt_summable(l))
                sum = pt_sum_add(sum, pt_sum_of(l));
            else
                ++rejected;
        }
        pt_add_to_pixel(px, py, sum, params.sampleCount, rejected);
    }
}
