// pt_light.glsl - direct lighting: next-event estimation from point, spot and area lights with
// MIS against BSDF sampling (pt_next_event), and the light pdf and MIS weight the integrator also
// uses for emitters its BSDF samples hit.
// Part of the path tracer; include pt/pt_trace.glsl rather than this file. Depends on
// pt_intersect.glsl (pt_visible, pt_shape_normal), pt_bsdf.glsl (pt_bsdf_eval), the accessors
// pt_light, pt_shape, pt_material and pt_globals, the plan's PT_OFF_LIGHT_* and PT_MIS, and the
// scene features (the light and shape types present).
// Shared verbatim with the C++ reference tracer: keep to the subset pt_trace.glsl describes (float
// literals with an f suffix, no swizzles, no in/out params).
#ifndef PT_LIGHT_GLSL
#define PT_LIGHT_GLSL

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
    vec3 shift = pt_shape_shift(s, time);
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
    // integrates at; the offset origin only starts the shadow ray. Testing at the origin but taking
    // the pdf at x would let points lying in the light's plane through with a cosine of 0 at x: a
    // clamped pdf of ~3e30, whose square in the MIS weight is inf / inf = NaN.
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

#endif // PT_LIGHT_GLSL
