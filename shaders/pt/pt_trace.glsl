// pt_trace.glsl - the path tracer, shared verbatim by the GPU kernel (pt_render.comp) and the
// C++ reference tracer (host/render/tracer_cpu.cpp, compiled with GLM). Keep to the common subset:
// float literals with an f suffix, no swizzles (vec3(v4) instead of v4.xyz), no in/out params.
//
// The includer provides, before including this file:
//   accessors  PtShape pt_shape(uint), PtMaterial pt_material(uint), PtLight pt_light(uint),
//              PtNode pt_node(uint), PtGlobals pt_globals(), OasPattern pt_pattern() (only
//              without PT_FETCH_GROUP: pt_group_dims is its one caller)
//   constants  the plan entries of pt/pt_constants.glsl (PT_PLAN_CONSTANTS: the effects, PT_MAX_DEPTH,
//              PT_RR_START and the dimension plan, PT_ABSENT where the plan has no such dimension),
//              and the scene features (PT_SCENE_FEATURE_CONSTANTS) when it defines PT_SCENE_FEATURES.
// Only the effects a scene calls for consume sample dimensions; the GPU kernel receives all of
// the above as specialization constants, so absent effects compile away.
#ifndef PT_TRACE_GLSL
#define PT_TRACE_GLSL

// The scene's features: which shape types, conductor materials and point/spot lights it has.
// Lavapipe runs both sides of every branch (its lanes are predicated, not branched), so each
// shape test paid for the sphere, quad and triangle code, whatever the shape. The GPU kernel
// defines PT_SCENE_FEATURES and receives them as specialization constants, so a feature the scene
// lacks compiles away; the code for a feature that is present is unchanged, and so are the
// images. The CPU tracer, which branches for real, keeps every path.
#include "pt/pt_constants.glsl"
#ifndef PT_SCENE_FEATURES
PT_SCENE_FEATURE_CONSTANTS(PT_DECLARE_DEFAULT)
#endif

const float PT_PI = 3.14159265358979f;
const float PT_INF = 1e30f;

/// The sample being traced: the pixel's OA seed and the sample index.
struct PtSampleState {
    uint seed;
    uint index;
};


/// Most dimensions of one group: the camera's (pixel, lens, time: 6 with the alignment gap) or one
/// path vertex's (light.uv, bsdf.uv, light.select, lobe, roulette: 8 with the gap). The library's
/// oas_draw fetches a group; host/render/plan.hpp's kMaxGroupDims is checked against this.
const uint PT_GROUP_MAX = OAS_DRAW_MAX;

/// Dimensions the camera group uses: pixel, then lens and time where present (not the alignment
/// gap before the first vertex group).
uint pt_camera_dims_used()
{
    return PT_HAS_MOTION ? PT_DIM_TIME + 1u : (PT_HAS_LENS ? PT_DIM_LENS + 2u : PT_DIM_PIXEL + 2u);
}

/// Dimensions a vertex group uses: up to its last present effect (not the alignment gap).
uint pt_vertex_dims_used()
{
    uint n = 0u;
    if (PT_OFF_LIGHT_UV != PT_ABSENT) n = max(n, PT_OFF_LIGHT_UV + 2u);
    if (PT_OFF_BSDF_UV != PT_ABSENT) n = max(n, PT_OFF_BSDF_UV + 2u);
    if (PT_OFF_LIGHT_SELECT != PT_ABSENT) n = max(n, PT_OFF_LIGHT_SELECT + 1u);
    if (PT_OFF_LOBE != PT_ABSENT) n = max(n, PT_OFF_LOBE + 1u);
    if (PT_OFF_RR != PT_ABSENT) n = max(n, PT_OFF_RR + 1u);
    return n;
}

/// Fetches a whole group at once, straight from the OA library (no sample buffers): oas_draw, the
/// library's one sample-fetch call. pt_radiance calls this at one site only: the GPU compiler
/// inlines the sampler wherever it is called, and with a call per use (a dozen in this file) the
/// lavapipe pipeline build took ~20 s, against ~0.1 s with the sampler replaced by one hash.
#ifdef PT_FETCH_GROUP
// The host's twin may supply its own fetch with the same values (host/render/tracer_cpu.cpp).
OasDraw pt_group_dims(PtSampleState st, uint first, uint count) { return PT_FETCH_GROUP(st, first, count); }
#else
OasDraw pt_group_dims(PtSampleState st, uint first, uint count)
{
    return oas_draw(pt_pattern(), st.seed, st.index, first, count);
}
#endif

/// First dimension of vertex v's group (v = 1 is the first surface hit).
uint pt_vertex_dim(uint v, uint offset) { return PT_DIM_VERTEX_BASE + (v - 1u) * PT_DIM_VERTEX_STRIDE + offset; }

uint pt_shape_type(PtShape s) { return uint(s.e.x); }
uint pt_shape_material(PtShape s) { return uint(s.e.y); }

/// Ray parameter of the hit with shape s at `time`, or PT_INF.
float pt_intersect_shape(PtShape s, vec3 o, vec3 d, float time, float tMin, float tMax)
{
    vec3 shift = vec3(s.d) * time;
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
        vec3 corner = vec3(s.a) + shift;
        vec3 eu = vec3(s.b);
        vec3 ev = vec3(s.c);
        vec3 n = cross(eu, ev);
        float denom = dot(d, n);
        if (abs(denom) < 1e-20f) return PT_INF;
        float t = dot(corner - o, n) / denom;
        if (!(t > tMin && t < tMax)) return PT_INF;
        vec3 p = o + d * t - corner;
        float nn = dot(n, n);
        float a = dot(cross(p, ev), n) / nn;
        float b = dot(cross(eu, p), n) / nn;
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
    if (PT_HAS_SPHERES && type == 0u) return normalize(p - (vec3(s.a) + vec3(s.d) * time));
    if (!PT_HAS_TRIANGLES || (PT_HAS_QUADS && type == 1u)) return normalize(cross(vec3(s.b), vec3(s.c)));
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

struct PtHit {
    float t;
    uint shape;  ///< PT_ABSENT: the ray escaped
};

/// Closest hit along o + t d, t in (tMin, tMax), through the BVH.
PtHit pt_trace(vec3 o, vec3 d, float time, float tMin, float tMax)
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
                }
            }
            if (sp == 0u) break;
            sp -= 1u;
            node = stack[sp];
            continue;
        }
        float tl = pt_box(pt_node(first), o, invD, hit.t);
        float tr = pt_box(pt_node(first + 1u), o, invD, hit.t);
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

/// True when nothing blocks the segment o + t d, t in (tMin, tMax).
bool pt_visible(vec3 o, vec3 d, float time, float tMin, float tMax)
{
    return pt_trace(o, d, time, tMin, tMax).shape == PT_ABSENT;
}

/// Orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
vec3 pt_tangent(vec3 n)
{
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z);
    return vec3(1.0f + s * n.x * n.x * a, s * n.x * n.y * a, -s * n.x);
}
vec3 pt_bitangent(vec3 n)
{
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z);
    return vec3(n.x * n.y * a, s + n.y * n.y * a, -n.y);
}
vec3 pt_to_world(vec3 local, vec3 n) { return pt_tangent(n) * local.x + pt_bitangent(n) * local.y + n * local.z; }

// --- GGX microfacets (Walter et al. 2007) ------------------------------------------------------
float pt_ggx_d(float cosM, float alpha)
{
    float a2 = alpha * alpha;
    float c2 = cosM * cosM;
    float denom = c2 * (a2 - 1.0f) + 1.0f;
    return a2 / (PT_PI * denom * denom);
}
float pt_ggx_g1(float cosV, float alpha)
{
    float c2 = max(cosV * cosV, 1e-12f);
    float tan2 = (1.0f - c2) / c2;
    return 2.0f / (1.0f + sqrt(1.0f + alpha * alpha * tan2));
}
/// A microfacet normal distributed as D(m) cos(m) about n.
vec3 pt_ggx_sample(vec3 n, float alpha, float u1, float u2)
{
    float tan2 = alpha * alpha * u1 / max(1.0f - u1, 1e-7f);
    float cosT = 1.0f / sqrt(1.0f + tan2);
    float sinT = sqrt(max(0.0f, 1.0f - cosT * cosT));
    float phi = 2.0f * PT_PI * u2;
    return pt_to_world(vec3(sinT * cos(phi), sinT * sin(phi), cosT), n);
}
vec3 pt_schlick(vec3 f0, float cosI)
{
    float m = 1.0f - clamp(cosI, 0.0f, 1.0f);
    float m5 = m * m * m * m * m;
    return f0 + (vec3(1.0f) - f0) * m5;
}
/// Unpolarised Fresnel reflectance at a dielectric interface; eta = n_incident / n_transmitted.
float pt_fresnel_dielectric(float cosI, float eta)
{
    float sin2T = eta * eta * max(0.0f, 1.0f - cosI * cosI);
    if (sin2T >= 1.0f) return 1.0f;
    float cosT = sqrt(1.0f - sin2T);
    float rs = (eta * cosI - cosT) / (eta * cosI + cosT);
    float rp = (cosI - eta * cosT) / (cosI + eta * cosT);
    return 0.5f * (rs * rs + rp * rp);
}

/// Alpha below which a conductor is a perfect mirror (a delta BSDF: no light sampling).
const float PT_SMOOTH_ALPHA = 1e-3f;

/// BSDF value f(wo, wi) * |cos wi| and the pdf of sampling wi, for non-delta diffuse and conductor
/// materials; n faces wo.
struct PtBsdfEval {
    vec3 fCos;
    float pdf;
};
PtBsdfEval pt_bsdf_eval(PtMaterial m, vec3 n, vec3 wo, vec3 wi)
{
    PtBsdfEval e;
    e.fCos = vec3(0.0f);
    e.pdf = 0.0f;
    float cosI = dot(n, wi);
    float cosO = dot(n, wo);
    if (cosI <= 0.0f || cosO <= 0.0f) return e;
    if (!(PT_HAS_CONDUCTORS || PT_HAS_DIELECTRIC) || m.albedo.w == PT_MAT_DIFFUSE) {
        e.fCos = vec3(m.albedo) * (cosI / PT_PI);
        e.pdf = cosI / PT_PI;
        return e;
    }
    float alpha = m.emission.w;
    vec3 h = normalize(wi + wo);
    float cosH = dot(n, h);
    float d = pt_ggx_d(cosH, alpha);
    float g = pt_ggx_g1(cosO, alpha) * pt_ggx_g1(cosI, alpha);
    vec3 f = pt_schlick(vec3(m.albedo), dot(wi, h));
    e.fCos = f * (d * g / (4.0f * cosO));
    e.pdf = d * cosH / (4.0f * max(dot(wo, h), 1e-7f));
    return e;
}

struct PtBsdfSample {
    vec3 wi;
    vec3 weight;   ///< f cos / pdf
    float pdf;     ///< 0 for delta lobes (then MIS does not apply)
    bool valid;
    bool specular; ///< delta or dielectric: the next emitter hit is not light-sampled here
};

/// Samples wi for outgoing wo at a surface with geometric normal ng (either side).
PtBsdfSample pt_bsdf_sample(PtMaterial m, vec3 ng, vec3 wo, float u1, float u2, float uLobe)
{
    PtBsdfSample s;
    s.valid = false;
    s.specular = false;
    s.pdf = 0.0f;
    s.weight = vec3(0.0f);
    s.wi = vec3(0.0f, 0.0f, 1.0f);
    bool outside = dot(ng, wo) >= 0.0f;
    vec3 n = outside ? ng : -ng;
    float cosO = dot(n, wo);
    float alpha = m.emission.w;
    if (!(PT_HAS_CONDUCTORS || PT_HAS_DIELECTRIC) || m.albedo.w == PT_MAT_DIFFUSE) {
        float r = sqrt(u1);
        float phi = 2.0f * PT_PI * u2;
        s.wi = pt_to_world(vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0f, 1.0f - u1))), n);
        s.pdf = dot(n, s.wi) / PT_PI;
        s.weight = vec3(m.albedo);
        s.valid = s.pdf > 0.0f;
        return s;
    }
    if (PT_HAS_CONDUCTORS && (!PT_HAS_DIELECTRIC || m.albedo.w == PT_MAT_CONDUCTOR)) {
        if (alpha < PT_SMOOTH_ALPHA) {
            s.wi = reflect(-wo, n);
            s.weight = pt_schlick(vec3(m.albedo), cosO);
            s.specular = true;
            s.valid = cosO > 0.0f;
            return s;
        }
        vec3 h = pt_ggx_sample(n, alpha, u1, u2);
        s.wi = reflect(-wo, h);
        float cosI = dot(n, s.wi);
        float cosH = dot(n, h);
        float oh = dot(wo, h);
        if (cosI <= 0.0f || cosO <= 0.0f || oh <= 0.0f) return s;
        s.weight = pt_schlick(vec3(m.albedo), dot(s.wi, h)) *
                   (pt_ggx_g1(cosO, alpha) * pt_ggx_g1(cosI, alpha) * oh / (cosO * cosH));
        s.pdf = pt_ggx_d(cosH, alpha) * cosH / (4.0f * oh);
        s.valid = true;
        return s;
    }
    // Dielectric, smooth or rough: choose reflection or refraction by the Fresnel term at the
    // (micro)normal with the lobe dimension, so F cancels from the weight.
    float eta = outside ? 1.0f / m.params.x : m.params.x;
    vec3 h = alpha < PT_SMOOTH_ALPHA ? n : pt_ggx_sample(n, alpha, u1, u2);
    float oh = dot(wo, h);
    if (oh <= 0.0f) return s;
    float fr = pt_fresnel_dielectric(oh, eta);
    s.specular = true;
    if (uLobe < fr) {
        s.wi = reflect(-wo, h);
        if (dot(n, s.wi) <= 0.0f) return s;
    } else {
        s.wi = refract(-wo, h, eta);
        if (dot(n, s.wi) >= 0.0f || dot(s.wi, s.wi) == 0.0f) return s;
    }
    float gWeight = 1.0f;
    if (alpha >= PT_SMOOTH_ALPHA)
        gWeight = pt_ggx_g1(cosO, alpha) * pt_ggx_g1(abs(dot(n, s.wi)), alpha) * oh / (cosO * dot(n, h));
    s.weight = vec3(m.albedo) * gWeight;
    s.valid = true;
    return s;
}

/// Power-heuristic MIS weight a^2 / (a^2 + b^2) of a strategy with pdf a against one with pdf b,
/// formed from the ratio of the smaller pdf to the larger (at most 1) so that no square overflows:
/// a grazing light sample's pdf can exceed float's sqrt(max) ~1.8e19, and inf / inf is NaN.
float pt_mis(float a, float b)
{
    if (!(a > 0.0f)) return 0.0f;
    if (a >= b) {
        float r = b / a;
        return 1.0f / (1.0f + r * r);
    }
    float r = a / b;
    return (r * r) / (1.0f + r * r);
}

/// Solid-angle pdf of light-sampling the point p (normal nl, area) from x, selection included.
float pt_light_pdf(vec3 x, vec3 p, vec3 nl, float area, float lightCount)
{
    vec3 d = p - x;
    float dist2 = dot(d, d);
    float cosL = abs(dot(nl, d)) / sqrt(dist2);
    return dist2 / max(cosL * area * lightCount, 1e-30f);
}

/// Offset for spawning rays off a surface at p, scaled with the coordinates' magnitude.
float pt_epsilon(vec3 p) { return 1e-4f * (1.0f + max(max(abs(p.x), abs(p.y)), abs(p.z))); }

/// Next-event estimation at x (normal n facing wo): one light, chosen uniformly with the
/// light-select dimension, sampled with the light dimensions; MIS against BSDF sampling.
vec3 pt_next_event(OasDraw d, PtMaterial m, vec3 x, vec3 n, vec3 wo, float time)
{
    PtGlobals g = pt_globals();
    float lightCount = g.time.z;
    if (lightCount < 1.0f) return vec3(0.0f);
    uint li = 0u;
    if (PT_OFF_LIGHT_SELECT != PT_ABSENT)
        li = min(uint(d.u[PT_OFF_LIGHT_SELECT] * lightCount), uint(lightCount) - 1u);
    PtLight light = pt_light(li);
    float eps = pt_epsilon(x);
    vec3 origin = x + n * eps;
    if (PT_HAS_POINT_LIGHTS && light.position.w != PT_LIGHT_AREA) {
        vec3 toL = vec3(light.position) - origin;
        float dist2 = dot(toL, toL);
        vec3 wi = toL / sqrt(dist2);
        PtBsdfEval e = pt_bsdf_eval(m, n, wo, wi);
        if (e.pdf <= 0.0f) return vec3(0.0f);
        float falloff = 1.0f;
        if (light.position.w == PT_LIGHT_SPOT) {
            float c = dot(-wi, vec3(light.spot));
            // smoothstep is undefined for equal edges: a spot without a soft rim has a hard edge.
            falloff = light.extra.x > light.spot.w ? smoothstep(light.spot.w, light.extra.x, c)
                                                  : (c >= light.spot.w ? 1.0f : 0.0f);
        }
        if (falloff <= 0.0f || !pt_visible(origin, wi, time, 0.0f, sqrt(dist2) * (1.0f - 1e-4f))) return vec3(0.0f);
        return e.fCos * vec3(light.intensity) * (falloff * lightCount / dist2);
    }
    if (PT_OFF_LIGHT_UV == PT_ABSENT) return vec3(0.0f);
    uint si = uint(light.intensity.w);
    PtShape s = pt_shape(si);
    float u1 = d.u[PT_OFF_LIGHT_UV];
    float u2 = d.u[PT_OFF_LIGHT_UV + 1u];
    vec3 shift = vec3(s.d) * time;
    vec3 p;
    uint type = pt_shape_type(s);
    if (PT_HAS_SPHERES && type == 0u) {
        float z = 1.0f - 2.0f * u1;
        float r = sqrt(max(0.0f, 1.0f - z * z));
        float phi = 2.0f * PT_PI * u2;
        p = vec3(s.a) + shift + vec3(r * cos(phi), r * sin(phi), z) * s.a.w;
    } else if (!PT_HAS_TRIANGLES || (PT_HAS_QUADS && type == 1u)) {
        p = vec3(s.a) + shift + vec3(s.b) * u1 + vec3(s.c) * u2;
    } else {
        float su = sqrt(u1);
        p = (vec3(s.a) * (1.0f - su) + vec3(s.b) * (su * (1.0f - u2)) + vec3(s.c) * (su * u2)) + shift;
    }
    vec3 nl = pt_shape_normal(s, p, time);
    // Direction, front-facing test and pdf all from the shading point x, the point the estimator
    // integrates at; the offset origin only starts the shadow ray. (Testing at the origin but taking
    // the pdf at x let points lying in the light's plane through with a cosine of 0 at x: a clamped
    // pdf of ~3e30 whose square in the MIS weight was inf / inf = NaN, as in interior_deep.)
    vec3 toL = p - x;
    vec3 wi = normalize(toL);
    if (!(dot(nl, -wi) > 0.0f)) return vec3(0.0f);  // emitters light their front side only
    PtBsdfEval e = pt_bsdf_eval(m, n, wo, wi);
    if (e.pdf <= 0.0f) return vec3(0.0f);
    vec3 toShadow = p - origin;
    float shadowDist = length(toShadow);
    if (!pt_visible(origin, toShadow / shadowDist, time, 0.0f, shadowDist * (1.0f - 1e-4f) - pt_epsilon(p)))
        return vec3(0.0f);
    float lightPdf = pt_light_pdf(x, p, nl, s.e.z, lightCount);
    float w = PT_MIS ? pt_mis(lightPdf, e.pdf) : 1.0f;
    return e.fCos * vec3(pt_material(pt_shape_material(s)).emission) * (w / lightPdf);
}

/// Radiance of one camera sample through pixel (px, py).
vec3 pt_radiance(PtSampleState st, uint px, uint py)
{
    PtGlobals g = pt_globals();
    float lightCount = g.time.z;
    vec3 origin = vec3(g.cameraPosition);
    vec3 dir = vec3(g.cameraForward);
    float time = g.time.x;

    vec3 radiance = vec3(0.0f);
    vec3 throughput = vec3(1.0f);
    bool lastSpecular = true;  // the camera ray: emitters it hits count fully
    float lastPdf = 0.0f;
    vec3 lastPosition = origin;
    // Group 0 is the camera ray (its dimensions [0, PT_DIM_VERTEX_BASE)), group v >= 1 the path
    // vertex v; every sample dimension is fetched by the one pt_group_dims call below.
    uint cameraDims = pt_camera_dims_used();
    uint vertexDims = pt_vertex_dims_used();
    for (uint v = 0u; v <= PT_MAX_DEPTH + 1u; ++v) {
        uint first = v == 0u ? 0u : pt_vertex_dim(v, 0u);
        uint count = v == 0u ? cameraDims : (v > PT_MAX_DEPTH ? 0u : vertexDims);
        OasDraw d = pt_group_dims(st, first, count);
        if (v == 0u) {
            float sx = (float(px) + d.u[PT_DIM_PIXEL]) / g.image.x * 2.0f - 1.0f;
            float sy = 1.0f - (float(py) + d.u[PT_DIM_PIXEL + 1u]) / g.image.y * 2.0f;
            vec3 forward = vec3(g.cameraForward);
            dir = normalize(forward + vec3(g.cameraRight) * (sx * g.cameraRight.w) + vec3(g.cameraUp) * (sy * g.cameraUp.w));
            if (PT_HAS_LENS) {
                vec3 focus = origin + dir * (g.cameraForward.w / dot(dir, forward));
                float r = g.cameraPosition.w * sqrt(d.u[PT_DIM_LENS]);
                float phi = 2.0f * PT_PI * d.u[PT_DIM_LENS + 1u];
                origin = origin + vec3(g.cameraRight) * (r * cos(phi)) + vec3(g.cameraUp) * (r * sin(phi));
                dir = normalize(focus - origin);
            }
            if (PT_HAS_MOTION) time = mix(g.time.x, g.time.y, d.u[PT_DIM_TIME]);
            lastPosition = origin;
            continue;
        }
        PtHit hit = pt_trace(origin, dir, time, 0.0f, PT_INF);
        if (hit.shape == PT_ABSENT) {
            radiance += throughput * vec3(g.environment);  // the environment is not light-sampled
            break;
        }
        PtShape s = pt_shape(hit.shape);
        PtMaterial m = pt_material(pt_shape_material(s));
        vec3 x = origin + dir * hit.t;
        vec3 ng = pt_shape_normal(s, x, time);
        vec3 wo = -dir;
        vec3 emission = vec3(m.emission);
        if ((emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f) && dot(ng, wo) > 0.0f) {
            float w = 1.0f;
            if (!lastSpecular && PT_NEE && PT_MIS && PT_OFF_LIGHT_UV != PT_ABSENT)
                w = pt_mis(lastPdf, pt_light_pdf(lastPosition, x, ng, s.e.z, lightCount));
            else if (!lastSpecular && PT_NEE)
                w = 0.0f;  // light sampling alone accounts for emitters seen from this vertex
            radiance += throughput * emission * w;
        }
        if (v > PT_MAX_DEPTH) break;
        vec3 n = dot(ng, wo) >= 0.0f ? ng : -ng;
        bool dielectric = m.albedo.w == PT_MAT_DIELECTRIC;
        bool delta = dielectric || (m.albedo.w == PT_MAT_CONDUCTOR && m.emission.w < PT_SMOOTH_ALPHA);
        if (PT_NEE && !delta) radiance += throughput * pt_next_event(d, m, x, n, wo, time);
        // Continue only where the plan has BSDF dimensions: always below the depth limit, and at
        // the last vertex only for MIS (to catch emitters by BSDF sampling).
        if (PT_OFF_BSDF_UV == PT_ABSENT || (v == PT_MAX_DEPTH && !(PT_MIS && PT_NEE))) break;
        float uLobe = 0.5f;
        if (PT_HAS_DIELECTRIC) uLobe = d.u[PT_OFF_LOBE];
        PtBsdfSample bs = pt_bsdf_sample(m, ng, wo, d.u[PT_OFF_BSDF_UV], d.u[PT_OFF_BSDF_UV + 1u], uLobe);
        if (!bs.valid) break;
        throughput *= bs.weight;
        lastSpecular = bs.specular;
        lastPdf = bs.pdf;
        lastPosition = x;
        if (PT_RR_START != 0u && v >= PT_RR_START && v < PT_MAX_DEPTH) {
            float survive = min(max(max(throughput.x, throughput.y), throughput.z), 0.95f);
            if (d.u[PT_OFF_RR] >= survive) break;
            throughput /= survive;
        }
        float side = dot(bs.wi, ng) >= 0.0f ? 1.0f : -1.0f;
        origin = x + ng * (side * pt_epsilon(x));
        dir = bs.wi;
    }
    return radiance;
}

#endif
