// pt_bsdf.glsl - the materials' BSDFs: diffuse, GGX conductors (or mirrors) and dielectrics
// (smooth or rough), evaluated (pt_bsdf_eval) and sampled (pt_bsdf_sample).
// Part of the path tracer; include pt/pt_trace.glsl rather than this file. Depends on pt_types.glsl
// (PtMaterial, PT_MAT_*), PT_PI and the features PT_HAS_CONDUCTORS and PT_HAS_DIELECTRIC.
// Shared verbatim with the C++ reference tracer: keep to the subset pt_trace.glsl describes (float
// literals with an f suffix, no swizzles, no in/out params).
#ifndef PT_BSDF_GLSL
#define PT_BSDF_GLSL

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

#endif // PT_BSDF_GLSL
