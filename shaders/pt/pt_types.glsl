// pt_types.glsl - the path tracer's scene data, shared by the GPU kernel (pt_render.comp, which
// reads each record's vec4s from a texel buffer of uvec4) and the C++ reference tracer
// (host/render/pt_types.hpp and tracer_cpu.cpp, through GLM).
// Everything is built from vec4 so the texel and C++ layouts agree without padding rules.
#ifndef PT_TYPES_GLSL
#define PT_TYPES_GLSL

const float PT_SHAPE_SPHERE = 0.0f;
const float PT_SHAPE_QUAD = 1.0f;
const float PT_SHAPE_TRIANGLE = 2.0f;

/// a: sphere centre / quad corner / triangle p0 (w: sphere radius); b: quad edgeU / triangle p1;
/// c: quad edgeV / triangle p2; d: velocity (world units per unit time); e: (type, material, area, 0).
/// Quads also carry m = cross(edgeU, edgeV) / |cross(edgeU, edgeV)|^2 in (a.w, b.w, c.w), made once
/// on the host (pt_quad_m): the intersection's plane normal and its edge-coordinate scale in one
/// vector, so a ray-quad test needs neither the cross product nor its two divisions.
struct PtShape {
    vec4 a;
    vec4 b;
    vec4 c;
    vec4 d;
    vec4 e;
};

const float PT_MAT_DIFFUSE = 0.0f;
const float PT_MAT_CONDUCTOR = 1.0f;
const float PT_MAT_DIELECTRIC = 2.0f;

/// albedo: (rgb, type); emission: (rgb, GGX alpha); params: (ior, 0, 0, 0).
struct PtMaterial {
    vec4 albedo;
    vec4 emission;
    vec4 params;
};

const float PT_LIGHT_POINT = 0.0f;
const float PT_LIGHT_SPOT = 1.0f;
const float PT_LIGHT_AREA = 2.0f;

/// position: (xyz, type); intensity: (rgb W/sr, area lights: shape index); spot: (axis, cosOuter);
/// extra: (cosInner, 0, 0, 0).
struct PtLight {
    vec4 position;
    vec4 intensity;
    vec4 spot;
    vec4 extra;
};

/// A BVH node (host/scene/bvh.hpp): lo/hi bounds with the child or first-shape index and the
/// shape count (0 = interior) stored as float bits.
struct PtNode {
    vec4 lo;
    vec4 hi;
};

/// Camera and scene constants.
struct PtGlobals {
    vec4 cameraPosition;  ///< w: aperture radius (0 = pinhole)
    vec4 cameraRight;     ///< unit; w: tan(fovY / 2) * aspect
    vec4 cameraUp;        ///< unit; w: tan(fovY / 2)
    vec4 cameraForward;   ///< unit; w: focus distance
    vec4 time;            ///< x: shutter open, y: shutter close, z: light count, w: node count
    vec4 environment;     ///< rgb radiance; w: image width
    vec4 image;           ///< x: width, y: height
};

#endif
