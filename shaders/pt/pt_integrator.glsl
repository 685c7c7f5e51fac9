// pt_integrator.glsl - the path integrator: the radiance of one camera sample (pt_radiance),
// a path with next-event estimation, MIS and Russian roulette as the plan calls for.
// The path is data: PtPath holds everything that carries from one vertex to the next, made by
// pt_path_begin from the camera group's dimensions and extended one vertex at a time by
// pt_path_step, so that a kernel can keep paths in memory between steps (a wavefront) and still run
// this one integrator. pt_radiance is the loop over the steps that the megakernel and the C++ twin
// run.
// Part of the path tracer; include pt/pt_trace.glsl rather than this file. Depends on every other
// part: pt_sample_dims.glsl, pt_intersect.glsl, pt_bsdf.glsl and pt_light.glsl; and on the
// accessors pt_globals, pt_shape and pt_material and the plan constants.
// Shared verbatim with the C++ reference tracer: keep to the subset pt_trace.glsl describes (float
// literals with an f suffix, no swizzles, no in/out params).
#ifndef PT_INTEGRATOR_GLSL
#define PT_INTEGRATOR_GLSL

/// A path between vertices: the next ray, what the path has gathered and carries, and what the
/// next vertex's emission needs of the last one (its MIS weight for the BSDF sample that left it).
/// Its two flags are uints (0 or 1), not bools: every field is then 4 bytes wide, and g++ keeps the
/// CPU twin's copy of the struct in registers. With two one-byte bools it assembled each step's
/// result on the stack and read it back in 16-byte pieces that overlapped the bytes just written,
/// which made blue_spheres9d's CPU renders 0.75-0.87x as fast (2-core AMD EPYC, alternated runs).
struct PtPath {
    vec3 origin;        ///< the next ray's origin
    vec3 dir;           ///< the next ray's direction (unit)
    vec3 radiance;      ///< the light gathered so far
    vec3 throughput;    ///< the path's weight so far (BSDF weights over pdfs, roulette's 1/survive)
    vec3 lastPosition;  ///< the vertex the next ray leaves (the camera for the first)
    float time;         ///< the sample's time in the shutter interval
    float lastPdf;      ///< the solid-angle pdf of the BSDF sample that made the next ray
    uint vertex;        ///< the vertex the next ray finds: 1 is the camera ray's hit
    uint lastSpecular;  ///< 1: the next ray left a delta lobe (or the camera), emitters count fully
    uint alive;         ///< 0 once the path has ended (escaped, absorbed, rouletted, depth)
};

/// The camera ray of pixel (px, py) from the camera group's dimensions (d: the group starting at
/// dimension 0): antialiasing, lens and time as the plan has them. g is pt_globals().
PtPath pt_path_begin(uint px, uint py, OasDraw d, PtGlobals g)
{
    PtPath p;
    p.origin = vec3(g.cameraPosition);
    p.time = g.time.x;
    vec3 forward = vec3(g.cameraForward);
    float sx = (float(px) + d.u[PT_DIM_PIXEL]) / g.image.x * 2.0f - 1.0f;
    float sy = 1.0f - (float(py) + d.u[PT_DIM_PIXEL + 1u]) / g.image.y * 2.0f;
    p.dir = normalize(forward + vec3(g.cameraRight) * (sx * g.cameraRight.w) + vec3(g.cameraUp) * (sy * g.cameraUp.w));
    if (PT_HAS_LENS) {
        vec3 focus = p.origin + p.dir * (g.cameraForward.w / dot(p.dir, forward));
        float r = g.cameraPosition.w * sqrt(d.u[PT_DIM_LENS]);
        float phi = 2.0f * PT_PI * d.u[PT_DIM_LENS + 1u];
        p.origin = p.origin + vec3(g.cameraRight) * (r * cos(phi)) + vec3(g.cameraUp) * (r * sin(phi));
        p.dir = normalize(focus - p.origin);
    }
    if (PT_HAS_MOTION) p.time = mix(g.time.x, g.time.y, d.u[PT_DIM_TIME]);
    p.radiance = vec3(0.0f);
    p.throughput = vec3(1.0f);
    p.lastPosition = p.origin;
    p.lastPdf = 0.0f;
    p.vertex = 1u;
    p.lastSpecular = 1u;  // the camera ray: emitters it hits count fully
    p.alive = 1u;
    return p;
}

/// A live path after its next vertex (p.vertex, whose group of dimensions is d): the ray's hit, the
/// emission there (MIS-weighted against the light sample of the vertex before), a light sample
/// (NEE), the BSDF sample that makes the next ray, and roulette. A path that ends comes back with
/// alive 0 and its radiance final. g is pt_globals(), which the caller reads once for all of a
/// path's steps (on the GPU it is seven texel fetches, which the compiler does not hoist out of the
/// loop by itself).
PtPath pt_path_step(PtPath p, OasDraw d, PtGlobals g)
{
    uint v = p.vertex;
    PtHit hit = pt_trace(p.origin, p.dir, p.time, 0.0f, PT_INF);
    if (hit.shape == PT_ABSENT) {
        p.radiance += p.throughput * vec3(g.environment);  // the environment is not light-sampled
        p.alive = 0u;
        return p;
    }
    PtShape s = pt_shape(hit.shape);
    PtMaterial m = pt_material(pt_shape_material(s));
    vec3 x = p.origin + p.dir * hit.t;
    vec3 ng = pt_shape_normal(s, x, p.time);
    vec3 wo = -p.dir;
    vec3 emission = vec3(m.emission);
    if ((emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f) && dot(ng, wo) > 0.0f) {
        float w = 1.0f;
        if (p.lastSpecular == 0u && PT_NEE && PT_MIS && PT_OFF_LIGHT_UV != PT_ABSENT)
            w = pt_mis(p.lastPdf, pt_light_pdf(p.lastPosition, x, ng, s.e.z, g.time.z));
        else if (p.lastSpecular == 0u && PT_NEE)
            w = 0.0f;  // light sampling alone accounts for emitters seen from this vertex
        p.radiance += p.throughput * emission * w;
    }
    p.alive = 0u;  // until the path survives every reason below to end here
    if (v > PT_MAX_DEPTH) return p;
    vec3 n = dot(ng, wo) >= 0.0f ? ng : -ng;
    bool dielectric = m.albedo.w == PT_MAT_DIELECTRIC;
    bool delta = dielectric || (m.albedo.w == PT_MAT_CONDUCTOR && m.emission.w < PT_SMOOTH_ALPHA);
    if (PT_NEE && !delta) p.radiance += p.throughput * pt_next_event(d, m, x, n, wo, p.time);
    // Continue only where the plan has BSDF dimensions: always below the depth limit, and at
    // the last vertex only for MIS (to catch emitters by BSDF sampling).
    if (PT_OFF_BSDF_UV == PT_ABSENT || (v == PT_MAX_DEPTH && !(PT_MIS && PT_NEE))) return p;
    float uLobe = 0.5f;
    if (PT_HAS_DIELECTRIC) uLobe = d.u[PT_OFF_LOBE];
    PtBsdfSample bs = pt_bsdf_sample(m, ng, wo, d.u[PT_OFF_BSDF_UV], d.u[PT_OFF_BSDF_UV + 1u], uLobe);
    if (!bs.valid) return p;
    p.throughput *= bs.weight;
    p.lastSpecular = bs.specular ? 1u : 0u;
    p.lastPdf = bs.pdf;
    p.lastPosition = x;
    if (PT_RR_START != 0u && v >= PT_RR_START && v < PT_MAX_DEPTH) {
        float survive = min(max(max(p.throughput.x, p.throughput.y), p.throughput.z), 0.95f);
        if (d.u[PT_OFF_RR] >= survive) return p;
        p.throughput /= survive;
    }
    float side = dot(bs.wi, ng) >= 0.0f ? 1.0f : -1.0f;
    p.origin = x + ng * (side * pt_epsilon(x));
    p.dir = bs.wi;
    p.vertex = v + 1u;
    p.alive = 1u;
    return p;
}

/// Radiance of one camera sample through pixel (px, py): the camera group, then one step per
/// vertex until the path ends.
vec3 pt_radiance(PtSampleState st, uint px, uint py)
{
    // Group 0 is the camera ray (its dimensions [0, PT_DIM_VERTEX_BASE)), group v >= 1 the path
    // vertex v; every sample dimension is fetched by the one pt_group_dims call below (the GPU
    // compiler inlines the fetch at each call site, so one site keeps the kernel small).
    uint cameraDims = pt_camera_dims_used();
    uint vertexDims = pt_vertex_dims_used();
    PtGlobals g = pt_globals();
    // p is made by pt_path_begin at v = 0; the zeros only spare compilers a read before a write.
    PtPath p = PtPath(vec3(0.0f), vec3(0.0f), vec3(0.0f), vec3(0.0f), vec3(0.0f), 0.0f, 0.0f, 0u, 0u, 1u);
    for (uint v = 0u; v <= PT_MAX_DEPTH + 1u; ++v) {
#ifdef PT_ON_VERTEX
        // A kernel's probe of the lanes that reach vertex v (pt_render.comp's counting variant);
        // the path tracer and the C++ twin define none.
        PT_ON_VERTEX(v);
#endif
        uint first = v == 0u ? 0u : pt_vertex_dim(v, 0u);
        uint count = v == 0u ? cameraDims : (v > PT_MAX_DEPTH ? 0u : vertexDims);
        OasDraw d = pt_group_dims(st, first, count);
        if (v == 0u) {
            p = pt_path_begin(px, py, d, g);
            continue;
        }
        p = pt_path_step(p, d, g);
        if (p.alive == 0u) break;
    }
    return p.radiance;
}

#endif // PT_INTEGRATOR_GLSL
