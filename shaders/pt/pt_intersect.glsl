// pt_intersect.glsl - ray against scene: shape intersection and normals, the BVH walk (pt_trace)
// and shadow-ray visibility (pt_visible).
// Part of the path tracer; include pt/pt_trace.glsl rather than this file. Depends on pt_types.glsl
// (PtShape, PtNode), the accessors pt_shape, pt_node and pt_globals, PT_ABSENT, PT_INF and the
// scene features PT_HAS_SPHERES, PT_HAS_QUADS and PT_HAS_TRIANGLES (pt_trace.glsl).
// Shared verbatim with the C++ reference tracer: keep to the subset pt_trace.glsl describes (float
// literals with an f suffix, no swizzles, no in/out params).
#ifndef PT_INTERSECT_GLSL
#define PT_INTERSECT_GLSL

uint pt_shape_type(PtShape s) { return uint(s.e.x); }
uint pt_shape_material(PtShape s) { return uint(s.e.y); }
/// Where shape s has moved to at `time` (its velocity times time). In a scene where nothing moves
/// it is 0 without reading the velocity: a texel fetch and three multiplies fewer per shape test.
vec3 pt_shape_shift(PtShape s, float time) { return PT_HAS_MOVING_SHAPES ? vec3(s.d) * time : vec3(0.0f); }
/// A quad's m = cross(edgeU, edgeV) / |cross(edgeU, edgeV)|^2 (pt_types.glsl).
vec3 pt_quad_m(PtShape s) { return vec3(s.a.w, s.b.w, s.c.w); }

/// Ray parameter of the hit with shape s at `time`, or PT_INF.
float pt_intersect_shape(PtShape s, vec3 o, vec3 d, float time, float tMin, float tMax)
{
    vec3 shift = pt_shape_shift(s, time);
    uint type = pt_shape_type(s);
    if (PT_HAS_SPHERES && type == 0u) {
        vec3 oc = o - (vec3(s.a) + shift);
        float r = s.a.w;
        float b = dot(oc, d);
        float c = dot(oc, oc) - r * r;
        float disc = b * b - c;
        if (disc < 0.0f) return PT_INF;
        float sq = sqrt(disc);
        float t0 = -b - sq;
        float t1 = -b + sq;
        if (t0 > tMin && t0 < tMax) return t0;
        if (t1 > tMin && t1 < tMax) return t1;
        return PT_INF;
    }
    if (PT_HAS_QUADS && type == 1u) {
        // The hit p - corner = a eu + b ev has a = dot(cross(p, ev), n) / |n|^2 and
        // b = dot(cross(eu, p), n) / |n|^2 for n = cross(eu, ev); m = n / |n|^2 is stored.
        vec3 corner = vec3(s.a) + shift;
        vec3 m = pt_quad_m(s);
        float denom = dot(d, m);
        // A ray parallel to the plane (denom 0) makes t infinite or NaN, and a zero-area quad a
        // NaN m: the range test below rejects both, so there is no separate test for them.
        float t = dot(corner - o, m) / denom;
        if (!(t > tMin && t < tMax)) return PT_INF;
        vec3 p = o + d * t - corner;
        float a = dot(cross(p, vec3(s.c)), m);
        float b = dot(cross(vec3(s.b), p), m);
        return (a >= 0.0f && a <= 1.0f && b >= 0.0f && b <= 1.0f) ? t : PT_INF;
    }
    if (!PT_HAS_TRIANGLES) return PT_INF;
    // Triangle (Moller and Trumbore 1997).
    vec3 p0 = vec3(s.a) + shift;
    vec3 e1 = vec3(s.b) - vec3(s.a);
    vec3 e2 = vec3(s.c) - vec3(s.a);
    vec3 pv = cross(d, e2);
    float det = dot(e1, pv);
    if (abs(det) < 1e-20f) return PT_INF;
    float invDet = 1.0f / det;
    vec3 tv = o - p0;
    float u = dot(tv, pv) * invDet;
    if (u < 0.0f || u > 1.0f) return PT_INF;
    vec3 qv = cross(tv, e1);
    float v = dot(d, qv) * invDet;
    if (v < 0.0f || u + v > 1.0f) return PT_INF;
    float t = dot(e2, qv) * invDet;
    return (t > tMin && t < tMax) ? t : PT_INF;
}

/// Unit geometric normal of shape s at point p (on the surface at `time`).
vec3 pt_shape_normal(PtShape s, vec3 p, float time)
{
    uint type = pt_shape_type(s);
    if (PT_HAS_SPHERES && type == 0u) return normalize(p - (vec3(s.a) + pt_shape_shift(s, time)));
    if (!PT_HAS_TRIANGLES || (PT_HAS_QUADS && type == 1u)) return normalize(pt_quad_m(s));
    return normalize(cross(vec3(s.b) - vec3(s.a), vec3(s.c) - vec3(s.a)));
}

/// Entry distance of the ray into a node's box, or PT_INF (slab test; 1/d may be infinite).
float pt_box(PtNode n, vec3 o, vec3 invD, float tMax)
{
    vec3 t0 = (vec3(n.lo) - o) * invD;
    vec3 t1 = (vec3(n.hi) - o) * invD;
    vec3 tn = min(t0, t1);
    vec3 tf = max(t0, t1);
    float enter = max(max(tn.x, tn.y), max(tn.z, 0.0f));
    float leave = min(min(tf.x, tf.y), min(tf.z, tMax));
    return enter <= leave ? enter : PT_INF;
}

/// pt_box of the sibling nodes `first` and `first + 1` (an interior node's children). The includer
/// may supply its own with the same results (PT_CHILDREN_BOX: the C++ tracer tests each box four
/// lanes at once, host/render/tracer_cpu.cpp).
vec2 pt_children_box(uint first, vec3 o, vec3 invD, float tMax)
{
#ifdef PT_CHILDREN_BOX
    return PT_CHILDREN_BOX(first, o, invD, tMax);
#else
    return vec2(pt_box(pt_node(first), o, invD, tMax), pt_box(pt_node(first + 1u), o, invD, tMax));
#endif
}

struct PtHit {
    float t;
    uint shape;  ///< PT_ABSENT: the ray escaped
};

/// Closest hit along o + t d, t in (tMin, tMax), through the BVH; with anyHit, the first hit
/// found (for visibility, where whether there is one is all that counts: it ends the walk at the
/// first occluder instead of searching on for a closer one). Callers pass anyHit as a constant,
/// so each use compiles to its own walk.
PtHit pt_trace_walk(vec3 o, vec3 d, float time, float tMin, float tMax, bool anyHit)
{
    PtHit hit;
    hit.t = tMax;
    hit.shape = PT_ABSENT;
    if (uint(pt_globals().time.w) == 0u) return hit;
    // No zero direction components: 1/0 = inf meets 0 * inf = NaN in the slab test.
    vec3 dd = d;
    if (abs(dd.x) < 1e-20f) dd.x = 1e-20f;
    if (abs(dd.y) < 1e-20f) dd.y = 1e-20f;
    if (abs(dd.z) < 1e-20f) dd.z = 1e-20f;
    vec3 invD = vec3(1.0f) / dd;
    uint stack[64];  // host/scene/bvh.hpp: depth < kBvhMaxDepth = 64
    uint sp = 0u;
    uint node = 0u;
    if (pt_box(pt_node(0u), o, invD, hit.t) == PT_INF) return hit;
    while (true) {
        PtNode n = pt_node(node);
        uint first = floatBitsToUint(n.lo.w);
        uint count = floatBitsToUint(n.hi.w);
        if (count > 0u) {
            for (uint i = first; i < first + count; ++i) {
                float t = pt_intersect_shape(pt_shape(i), o, d, time, tMin, hit.t);
                if (t < hit.t) {
                    hit.t = t;
                    hit.shape = i;
                    if (anyHit) return hit;
                }
            }
            if (sp == 0u) break;
            sp -= 1u;
            node = stack[sp];
            continue;
        }
        vec2 tlr = pt_children_box(first, o, invD, hit.t);
        float tl = tlr.x;
        float tr = tlr.y;
        if (tl == PT_INF && tr == PT_INF) {
            if (sp == 0u) break;
            sp -= 1u;
            node = stack[sp];
            continue;
        }
        uint nearChild = tl <= tr ? first : first + 1u;
        uint farChild = tl <= tr ? first + 1u : first;
        if ((tl <= tr ? tr : tl) != PT_INF && sp < 64u) {
            stack[sp] = farChild;
            sp += 1u;
        }
        node = nearChild;
    }
    return hit;
}

/// Closest hit along o + t d, t in (tMin, tMax), through the BVH.
PtHit pt_trace(vec3 o, vec3 d, float time, float tMin, float tMax)
{
    return pt_trace_walk(o, d, time, tMin, tMax, false);
}

/// True when nothing blocks the segment o + t d, t in (tMin, tMax).
bool pt_visible(vec3 o, vec3 d, float time, float tMin, float tMax)
{
    return pt_trace_walk(o, d, time, tMin, tMax, true).shape == PT_ABSENT;
}

#endif // PT_INTERSECT_GLSL
