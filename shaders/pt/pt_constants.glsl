// pt_constants.glsl - the path tracer's one table of specialization constants and buffer
// bindings, shared verbatim by the GLSL kernel and the C++ host (both preprocessors take these
// function-like "X-macros"). Each fact is written here once; the users expand the tables:
//   pt_render.comp      layout(constant_id = ID) const TYPE NAME = DEFAULT; for every entry, and
//                       layout(binding = PT_BINDING_...) for its buffers
//   pt/pt_trace.glsl    const TYPE NAME = DEFAULT; for the scene features where the includer does
//                       not specialise them (PT_SCENE_FEATURES undefined: the CPU tracer)
//   host/render/pt_constants.hpp   struct pt::PtSpecialization, one field NAME per entry, set to
//                       DEFAULT; kAbsent (= PT_ABSENT); kBindingCount
//   host/render/tracer_gpu.cpp     specialization(): each field from its HOST expression; the
//                       kernel's {ID, value} list; buffers_[PT_BINDING_...]
//   host/render/tracer_cpu.cpp     one per-thread variable NAME for every plan entry, copied
//                       from the same specialization() (the CPU tracer's "specialization")
//
// A specialization-constant entry is X(NAME, ID, TYPE, DEFAULT, HOST):
//   NAME     the identifier the tracer (pt/pt_*.glsl) and pt_render.comp read
//   ID       its constant_id in pt_render.comp
//   TYPE     bool or uint (the GLSL type; the same spelling in C++)
//   DEFAULT  the value a pipeline gets without specialization (also PtSpecialization's initializer)
//   HOST     a C++ expression for its value in specialization() (host/render/tracer_gpu.cpp), over
//            `pattern` (oas::Pattern), `plan` (DimensionPlan), `stage` (KernelStage) and
//            `features` (SceneFeatures). GLSL never expands it.
// A new constant is one line here: both tracers and the GPU pipeline pick it up.
#ifndef PT_CONSTANTS_GLSL
#define PT_CONSTANTS_GLSL

/// "Absent", the one name for it: a dimension the plan does not have (host/render/plan.hpp,
/// whose kAbsent is this constant), a ray that hit nothing.
const uint PT_ABSENT = 0xffffffffu;

/// The sampler kind (oas/oas.glsl's OAS_STATIC_CONSTRUCTION, _OFFSET, _FIELD_KIND, _FIELD_DEGREE,
/// _SMALL_N, _INDEX_BITS).
#define PT_SAMPLER_CONSTANTS(X) \
    X(oasSpecConstruction, 0, uint, 1u, pattern.construction) \
    X(oasSpecOffset, 1, uint, 3u, pattern.offset) \
    X(oasSpecFieldKind, 2, uint, 0u, fieldKind(pattern)) \
    X(oasSpecFieldDegree, 3, uint, 1u, fieldDegree(pattern)) \
    X(oasSpecSmallN, 4, uint, 0u, smallN(pattern)) \
    X(oasSpecIndexBits, 5, uint, 24u, indexBits(pattern))

/// The effects and the dimension plan (host/render/plan.hpp): where each effect's sample
/// dimensions land, PT_ABSENT where the scene does not call for the effect. The CPU tracer reads
/// these per scene too.
#define PT_PLAN_CONSTANTS(X) \
    X(PT_HAS_LENS, 10, bool, false, plan.hasLens) \
    X(PT_HAS_MOTION, 11, bool, false, plan.hasMotion) \
    X(PT_NEE, 12, bool, true, plan.nee) \
    X(PT_MIS, 13, bool, true, plan.mis) \
    X(PT_HAS_DIELECTRIC, 14, bool, false, plan.lobe != PT_ABSENT) \
    X(PT_MAX_DEPTH, 15, uint, 1u, plan.maxDepth) \
    X(PT_RR_START, 16, uint, 0u, plan.roulette != PT_ABSENT ? plan.rouletteStart : 0u) \
    X(PT_DIM_PIXEL, 20, uint, 0u, plan.pixel) \
    X(PT_DIM_LENS, 21, uint, PT_ABSENT, plan.lens) \
    X(PT_DIM_TIME, 22, uint, PT_ABSENT, plan.time) \
    X(PT_DIM_VERTEX_BASE, 23, uint, 2u, plan.vertexBase) \
    X(PT_DIM_VERTEX_STRIDE, 24, uint, 2u, plan.vertexStride) \
    X(PT_OFF_LIGHT_SELECT, 25, uint, PT_ABSENT, plan.lightSelect) \
    X(PT_OFF_LIGHT_UV, 26, uint, PT_ABSENT, plan.lightUV) \
    X(PT_OFF_BSDF_UV, 27, uint, PT_ABSENT, plan.bsdfUV) \
    X(PT_OFF_LOBE, 28, uint, PT_ABSENT, plan.lobe) \
    X(PT_OFF_RR, 29, uint, PT_ABSENT, plan.roulette)

/// Profile by elimination (oas-render-bench --profile; KernelStage in host/render/tracer.hpp):
/// what the kernel does per sample. 0: the path tracer; 1: nothing (dispatch, bounds test and
/// accumulation only); 2: the sample fetches alone. Renders use 0; the other branches compile away.
/// PT_PREFETCH_DIMS: 0, or the kernel reads its sample values from the samples texel buffer,
/// which the generation kernel (oas_generate.comp) filled for the batch just before, this many
/// dimensions per (pixel, sample), a multiple of 4. GpuTracer sets it (host/render/tracer.hpp,
/// prefetchDims, which reads the plan constants through specialization(): not a HOST expression).
/// PT_WAVEFRONT_STAGE: which of pt_wavefront.comp's three kernels a pipeline is (0 the camera
/// rays, 1 one step of the live paths, 2 the pixels' sums); the host sets it per pipeline
/// (host/render/wavefront_gpu.cpp), pt_render.comp ignores it.
#define PT_KERNEL_CONSTANTS(X) \
    X(PT_STAGE, 30, uint, 0u, stage) \
    X(PT_PREFETCH_DIMS, 37, uint, 0u, 0u) \
    X(PT_WAVEFRONT_STAGE, 38, uint, 0u, 0u)

/// The scene's features (host/render/scene_data.hpp SceneFeatures; defaults in pt/pt_trace.glsl,
/// tests in pt_intersect, pt_bsdf and pt_light.glsl): the defaults keep every path, the GPU kernel
/// compiles away what the scene lacks.
#define PT_SCENE_FEATURE_CONSTANTS(X) \
    X(PT_HAS_SPHERES, 31, bool, true, features.spheres) \
    X(PT_HAS_QUADS, 32, bool, true, features.quads) \
    X(PT_HAS_TRIANGLES, 33, bool, true, features.triangles) \
    X(PT_HAS_CONDUCTORS, 34, bool, true, features.conductors) \
    X(PT_HAS_POINT_LIGHTS, 35, bool, true, features.pointLights) \
    X(PT_HAS_MOVING_SHAPES, 36, bool, true, features.movingShapes)

/// Every specialization constant of pt_render.comp, in constant_id order.
#define PT_SPEC_CONSTANTS(X) \
    PT_SAMPLER_CONSTANTS(X) PT_PLAN_CONSTANTS(X) PT_KERNEL_CONSTANTS(X) PT_SCENE_FEATURE_CONSTANTS(X)

/// An entry as a plain constant with its default.
#define PT_DECLARE_DEFAULT(NAME, ID, TYPE, DEFAULT, HOST) const TYPE NAME = DEFAULT;

/// pt_render.comp's buffers, X(NAME, BINDING, TEXELS): bindings 0 .. count - 1, each once.
/// TEXELS true: a read-only texel buffer of uvec4 (usamplerBuffer), for the scene data the
/// tracer reads; false: a storage buffer. Lavapipe loads a storage-buffer element one lane at a
/// time (even at an index all lanes share) and fetches texels for all lanes at once
/// (host/vk/context.hpp, BindingKind).
#define PT_BINDINGS(X) \
    X(PT_BINDING_SHAPES, 0u, true) \
    X(PT_BINDING_MATERIALS, 1u, true) \
    X(PT_BINDING_LIGHTS, 2u, true) \
    X(PT_BINDING_NODES, 3u, true) \
    X(PT_BINDING_GLOBALS, 4u, true) \
    X(PT_BINDING_ACCUMULATION, 5u, false) \
    X(PT_BINDING_SOBOL_DIRECTIONS, 6u, true) \
    X(PT_BINDING_SAMPLES, 7u, true)
#define PT_DECLARE_BINDING(NAME, BINDING, TEXELS) const uint NAME = BINDING;
PT_BINDINGS(PT_DECLARE_BINDING)

/// pt_wavefront.comp's buffers past PT_BINDINGS', X(NAME, BINDING): the live paths' records read
/// (a texel buffer of uvec4) and written (a storage texel buffer of uint), each path's radiance
/// when it ends (a storage texel buffer of uint), and the queue counters (a storage buffer).
#define PT_WAVEFRONT_BINDINGS(X) \
    X(PT_BINDING_PATHS_IN, 8u) \
    X(PT_BINDING_PATHS_OUT, 9u) \
    X(PT_BINDING_RESULTS, 10u) \
    X(PT_BINDING_COUNTERS, 11u)
#define PT_DECLARE_WAVEFRONT_BINDING(NAME, BINDING) const uint NAME = BINDING;
PT_WAVEFRONT_BINDINGS(PT_DECLARE_WAVEFRONT_BINDING)

/// pt_render.comp's lane-counting variant (PT_COUNT_OCCUPANCY) only, past PT_BINDINGS': per
/// vertex v, words 2v and 2v + 1 count the lanes that ran the loop at v and the subgroups that did.
const uint PT_BINDING_OCCUPANCY = 8u;

#endif
