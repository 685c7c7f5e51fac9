// pt_trace.glsl - the path tracer, shared verbatim by the GPU kernel (pt_render.comp) and the
// C++ reference tracer (host/render/tracer_cpu.cpp, compiled with GLM). Keep to the common subset:
// float literals with an f suffix, no swizzles (vec3(v4) instead of v4.xyz), no in/out params.
// This file is the includers' one entry: it declares what every part shares and includes the
// parts, each after those it calls:
//   pt_sample_dims.glsl   PtSampleState, the dimensions each group uses, pt_group_dims (the fetch)
//   pt_intersect.glsl     shape intersection and normals, the BVH walk pt_trace, pt_visible
//   pt_bsdf.glsl          diffuse, GGX conductor and dielectric BSDFs: pt_bsdf_eval, pt_bsdf_sample
//   pt_light.glsl         next-event estimation (pt_next_event), pt_light_pdf, pt_mis, pt_epsilon
//   pt_integrator.glsl    pt_radiance, the path of one camera sample
//
// The includer provides, before including this file:
//   accessors  PtShape pt_shape(uint), PtMaterial pt_material(uint), PtLight pt_light(uint),
//              PtNode pt_node(uint), PtGlobals pt_globals(), OasPattern pt_pattern() (only
//              without PT_FETCH_GROUP: pt_group_dims is its one caller)
//   constants  the plan entries of pt/pt_constants.glsl (PT_PLAN_CONSTANTS: the effects, PT_MAX_DEPTH,
//              PT_RR_START and the dimension plan, PT_ABSENT where the plan has no such dimension),
//              and the scene features (PT_SCENE_FEATURE_CONSTANTS) when it defines PT_SCENE_FEATURES.
//   optional   PT_FETCH_GROUP (its own pt_group_dims) and PT_CHILDREN_BOX (its own pt_children_box),
//              each giving the same results as the GLSL it replaces (the C++ tracer defines both).
// Only the effects a scene calls for consume sample dimensions; the GPU kernel receives all of
// the above as specialization constants, so absent effects compile away.
#ifndef PT_TRACE_GLSL
#define PT_TRACE_GLSL

// The scene's features: which shape types, conductor materials and point/spot lights it has, and
// whether any shape moves.
// Lavapipe runs both sides of every branch (its lanes are predicated, not branched), so without
// them every shape test would pay for the sphere, quad and triangle code, whatever the shape. The
// GPU kernel defines PT_SCENE_FEATURES and receives them as specialization constants, so a feature
// the scene lacks compiles away; a feature it has keeps the same code, so the images do not depend
// on the specialization. The CPU tracer, which branches for real, keeps every path.
#include "pt/pt_constants.glsl"
#ifndef PT_SCENE_FEATURES
PT_SCENE_FEATURE_CONSTANTS(PT_DECLARE_DEFAULT)
#endif

// Constants every part uses.
const float PT_PI = 3.14159265358979f;
const float PT_INF = 1e30f;  ///< "no hit": the distance pt_intersect_shape returns for a miss

// The tracer's parts, each after those it calls.
#include "pt/pt_sample_dims.glsl"
#include "pt/pt_intersect.glsl"
#include "pt/pt_bsdf.glsl"
#include "pt/pt_light.glsl"
#include "pt/pt_integrator.glsl"

#endif
