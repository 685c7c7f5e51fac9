// pt_integrator.glsl - the path integrator: the radiance of one camera sample (pt_radiance),
// a path with next-event estimation, MIS and Russian roulette as the plan calls for.
// Part of the path tracer; include pt/pt_trace.glsl rather than this file. Depends on every other
// part: pt_sample_dims.glsl, pt_intersect.glsl, pt_bsdf.glsl and pt_light.glsl; and on the
// accessors pt_globals, pt_shape and pt_material and the plan constants.
// Shared verbatim with the C++ reference tracer: keep to the subset pt_trace.glsl describes (float
// literals with an f suffix, no swizzles, no in/out params).
#ifndef PT_INTEGRATOR_GLSL
#define PT_INTEGRATOR_GLSL

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

#endif // PT_INTEGRATOR_GLSL
