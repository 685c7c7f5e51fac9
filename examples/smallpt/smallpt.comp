#version 450
// A small path tracer of the kind a renderer author writes, with oas embedded the way
// docs/EMBEDDING.md says: a room of five diffuse walls, a mirror sphere, a glass sphere and a
// spherical light; next-event estimation at diffuse vertices, Russian roulette. One invocation
// per pixel traces `samples` consecutive samples and adds them to the pixel's sum.
// Where its random numbers come from is a specialization constant (samplerMode):
//   0  its own integer hash of (pixel, sample, dimension): what it had before oas;
//   1  oas_draw for each group of numbers (the camera, a path vertex) where it is used;
//   2  values a prefetch kernel (prefetch.comp, oas_prefetch) wrote before this dispatch.
// Modes 1 and 2 give the same numbers bit for bit, so the same image (tests/smallpt_test.cpp).
// In modes 1 and 2 only the path's first `dims` dimensions (the camera and the first vertices:
// the host picks a vertex boundary) come from oas, the rest from the own hash: the recipe for
// renderers whose paths are too cheap to pay for stratifying every bounce.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// The include specialized on the pattern (oas_specialization fills these): what makes it fast.
layout(constant_id = 0) const uint specConstruction = 1u;
layout(constant_id = 1) const uint specOffset = 3u;
layout(constant_id = 2) const uint specFieldKind = 0u;
layout(constant_id = 3) const uint specFieldDegree = 1u;
layout(constant_id = 4) const uint specSmallN = 1u;
layout(constant_id = 5) const uint samplerMode = 0u;
#define OAS_STATIC_CONSTRUCTION specConstruction
#define OAS_STATIC_OFFSET specOffset
#define OAS_STATIC_FIELD_KIND specFieldKind
#define OAS_STATIC_FIELD_DEGREE specFieldDegree
#define OAS_STATIC_SMALL_N specSmallN
#define OAS_NO_SOBOL  // this renderer is never given a Sobol pattern
// The build for layouts whose draws (the camera's, a vertex's) each span at most this many OA
// blocks (smallpt.cpp's drawBlocks decides; CMakeLists.txt builds both): oas_draw then makes one
// row per block in reach instead of one wherever a block may start.
#ifdef SMALLPT_DRAW_BLOCKS
#define OAS_STATIC_DRAW_BLOCKS SMALLPT_DRAW_BLOCKS
#endif
#include "oas/oas.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant) uniform Params {
    OasPattern pattern;
    uint width;
    uint height;
    uint frameSeed;
    uint firstSample;  // this dispatch traces samples [firstSample, firstSample + samples)
    uint samples;
    uint dims;         // dimensions drawn from oas (the rest from the own hash): the prefetched values' stride
} params;

layout(std430, binding = 0) buffer Sums { vec4 sums[]; };  // per pixel: radiance summed over samples
// Mode 2: the prefetch kernel's values, [pixel][sample - firstSample][dim], read four to a texel
// (lavapipe fetches a texel for all lanes at once; a storage buffer one lane at a time).
layout(binding = 1) uniform usamplerBuffer prefetched;

// ---------------------------------------------------------------------------- random numbers

uint gPixel;
uint gPixelSeed;
uint gSample;

/// The renderer's own generator: a 32-bit integer hash (xorshift-multiply rounds) of the pixel
/// seed, sample and dimension.
uint ownHash(uint h)
{
    h ^= h >> 16u;
    h *= 0x7feb352du;
    h ^= h >> 15u;
    h *= 0x846ca68bu;
    h ^= h >> 16u;
    return h;
}

float ownRand(uint dim)
{
    return float(ownHash(gPixelSeed ^ ownHash(gSample * 0x9e3779b9u + ownHash(dim))) >> 8u) * (1.0 / 16777216.0);
}

/// Mode 2: dimension `dim` of the current sample as the prefetch kernel wrote it.
float prefetchedValue(uint dim)
{
    uint at = (gPixel * params.samples + (gSample - params.firstSample)) * params.dims + dim;
    return uintBitsToFloat(texelFetch(prefetched, int(at >> 2u))[at & 3u]);
}

/// Dimensions [firstDim, firstDim + n) of the current sample, n <= OAS_DRAW_MAX, drawn at one
/// place per use (the camera, the top of the vertex loop), not where each number is used: GPU
/// compilers inline the sampler at every call site, and lavapipe runs every side of a branch
/// that any lane takes, so a draw inside the material branches would be paid several times.
/// oas_draw also makes an OA block's row once for the block's dimensions in the group.
/// ownDraw: the own hash's numbers; oasDraw: oas's (modes 1 and 2), for dimensions below params.dims.
OasDraw ownDraw(uint firstDim, uint n)
{
    OasDraw d;
    [[unroll]] for (uint k = 0u; k < OAS_DRAW_MAX; ++k) d.u[k] = k < n ? ownRand(firstDim + k) : 0.0;
    return d;
}

OasDraw oasDraw(uint firstDim, uint n)
{
    if (samplerMode == 1u) return oas_draw(params.pattern, gPixelSeed, gSample, firstDim, n);
    OasDraw d;
    [[unroll]] for (uint k = 0u; k < OAS_DRAW_MAX; ++k) d.u[k] = k < n ? prefetchedValue(firstDim + k) : 0.0;
    return d;
}

/// Whether dimensions [firstDim, firstDim + n) come from oas. The host sets params.dims at a
/// vertex boundary, and every lane is at the same vertex, so the answer is the same in all lanes.
bool fromOas(uint firstDim, uint n) { return samplerMode != 0u && firstDim + n <= params.dims; }

// The dimension layout: 2D samples go where the pattern stratifies pairs (oas_pair_dimension:
// CMJ partners within one OA block), 1D samples on the next free dimension. The host runs the
// same sequence through the C API to size the prefetch (smallpt.cpp, pathDimensions).
uint gCursor;
uint next2D()
{
    uint d = oas_pair_dimension(params.pattern, gCursor);
    gCursor = d + 2u;
    return d;
}
uint next1D() { return gCursor++; }

// ---------------------------------------------------------------------------- scene

const float PI = 3.14159265358979;
const uint DIFFUSE = 0u, MIRROR = 1u, GLASS = 2u, LIGHT = 3u;
const uint MAX_DEPTH = 8u;
const vec3 LIGHT_CENTER = vec3(0.5, 0.9, 0.55);
const float LIGHT_RADIUS = 0.06;
const vec3 LIGHT_RADIANCE = vec3(40.0, 36.0, 30.0);

struct Hit {
    float t;
    vec3 normal;   // facing the ray's origin side for walls; outward for spheres
    vec3 albedo;
    uint material;
};

void hitSphere(vec3 o, vec3 d, vec3 c, float r, vec3 albedo, uint material, inout Hit h)
{
    vec3 oc = o - c;
    float b = dot(oc, d), det = b * b - (dot(oc, oc) - r * r);
    if (det < 0.0) return;
    float sq = sqrt(det);
    float t = -b - sq > 1e-4 ? -b - sq : -b + sq;
    if (t > 1e-4 && t < h.t) {
        h.t = t;
        h.normal = (o + t * d - c) / r;
        h.albedo = albedo;
        h.material = material;
    }
}

// An axis-aligned wall: coordinate `axis` of the point equals `at`.
void hitWall(vec3 o, vec3 d, uint axis, float at, vec3 albedo, inout Hit h)
{
    if (abs(d[axis]) < 1e-8) return;
    float t = (at - o[axis]) / d[axis];
    if (t > 1e-4 && t < h.t) {
        vec3 p = o + t * d;
        if (any(lessThan(p, vec3(-1e-3))) || any(greaterThan(p, vec3(1.0 + 1e-3)))) return;
        h.t = t;
        h.normal = vec3(0.0);
        h.normal[axis] = d[axis] > 0.0 ? -1.0 : 1.0;
        h.albedo = albedo;
        h.material = DIFFUSE;
    }
}

Hit intersect(vec3 o, vec3 d)
{
    Hit h;
    h.t = 1e30;
    h.material = DIFFUSE;
    hitWall(o, d, 0u, 0.0, vec3(0.75, 0.25, 0.25), h);  // left, red
    hitWall(o, d, 0u, 1.0, vec3(0.25, 0.35, 0.75), h);  // right, blue
    hitWall(o, d, 1u, 0.0, vec3(0.75), h);              // floor
    hitWall(o, d, 1u, 1.0, vec3(0.75), h);              // ceiling
    hitWall(o, d, 2u, 1.0, vec3(0.75), h);              // back
    hitSphere(o, d, vec3(0.28, 0.2, 0.62), 0.2, vec3(0.95), MIRROR, h);
    hitSphere(o, d, vec3(0.72, 0.2, 0.38), 0.2, vec3(0.98), GLASS, h);
    hitSphere(o, d, LIGHT_CENTER, LIGHT_RADIUS, vec3(0.0), LIGHT, h);
    return h;
}

// An orthonormal basis around n (Duff et al., "Building an Orthonormal Basis, Revisited", 2017).
mat3 basis(vec3 n)
{
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z), b = n.x * n.y * a;
    return mat3(vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x), vec3(b, s + n.y * n.y * a, -n.y), n);
}

// ---------------------------------------------------------------------------- the integrator

/// A path between two vertices: the ray leaving the last one, what it has gathered, whether it ended.
struct Path {
    vec3 o, d;
    vec3 sum, throughput;
    bool countEmission;  // camera rays and specular bounces see the light; diffuse ones use NEE
    bool ended;
};

/// Where a scattering vertex's numbers lie: its first dimension, then offsets from it.
struct VertexDims {
    uint first, light, bsdf, lobe, roulette, count;
};

/// The next vertex's dimensions (at most OAS_DRAW_MAX from the first: the host checks the layout,
/// smallpt.cpp's pathDimensions); advances the cursor past them.
VertexDims nextVertexDims()
{
    VertexDims v;
    v.first = gCursor;
    v.light = next2D() - v.first;
    v.bsdf = next2D() - v.first;
    v.lobe = next1D() - v.first;
    v.roulette = next1D() - v.first;
    v.count = gCursor - v.first;
    return v;
}

/// One scattering vertex: trace the ray, add emission and next-event estimation, sample the
/// BSDF, roulette; `u` holds the vertex's numbers at the offsets in `v`.
Path scatter(Path path, uint depth, OasDraw u, VertexDims v)
{
    Hit h = intersect(path.o, path.d);
    if (h.t >= 1e30) {
        path.ended = true;
        return path;
    }
    if (h.material == LIGHT) {
        if (path.countEmission) path.sum += path.throughput * LIGHT_RADIANCE;
        path.ended = true;
        return path;
    }
    vec3 d = path.d, p = path.o + h.t * d;
    if (h.material == DIFFUSE) {
        // Next-event estimation: a direction in the light's cone, uniform in solid angle.
        vec3 toLight = LIGHT_CENTER - p;
        float dist2 = dot(toLight, toLight);
        float cosMax = sqrt(max(0.0, 1.0 - LIGHT_RADIUS * LIGHT_RADIUS / dist2));
        float cosTheta = 1.0 - u.u[v.light] * (1.0 - cosMax);
        float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta)), phi = 2.0 * PI * u.u[v.light + 1u];
        vec3 l = basis(normalize(toLight)) * vec3(cos(phi) * sinTheta, sin(phi) * sinTheta, cosTheta);
        float cosSurface = dot(l, h.normal);
        if (cosSurface > 0.0 && intersect(p, l).material == LIGHT)
            path.sum += path.throughput * h.albedo / PI * LIGHT_RADIANCE * cosSurface * 2.0 * PI * (1.0 - cosMax);
        // Cosine-weighted bounce.
        float r = sqrt(u.u[v.bsdf]), a = 2.0 * PI * u.u[v.bsdf + 1u];
        d = basis(h.normal) * vec3(r * cos(a), r * sin(a), sqrt(max(0.0, 1.0 - r * r)));
        path.countEmission = false;
    } else if (h.material == MIRROR) {
        d = reflect(d, h.normal);
        path.countEmission = true;
    } else {  // glass, index 1.5: reflect or refract by Fresnel (Schlick)
        bool entering = dot(d, h.normal) < 0.0;
        vec3 n = entering ? h.normal : -h.normal;
        float eta = entering ? 1.0 / 1.5 : 1.5;
        vec3 refracted = refract(d, n, eta);
        float cosI = -dot(d, n), f0 = 0.04;
        float fresnel = dot(refracted, refracted) == 0.0 ? 1.0 : f0 + (1.0 - f0) * pow(1.0 - cosI, 5.0);
        d = u.u[v.lobe] < fresnel ? reflect(d, n) : refracted;
        path.countEmission = true;
    }
    path.throughput *= h.albedo;
    path.o = p;
    path.d = d;
    if (depth >= 2u) {  // Russian roulette
        float keep = min(0.95, max(path.throughput.r, max(path.throughput.g, path.throughput.b)));
        if (u.u[v.roulette] >= keep) {
            path.ended = true;
            return path;
        }
        path.throughput /= keep;
    }
    return path;
}

vec3 radiance(vec3 o, vec3 d)
{
    Path path = Path(o, d, vec3(0.0), vec3(1.0), true, false);
    uint depth = 0u;
    // Two loops over the same vertex: the first while the numbers come from oas, the second with
    // the own hash. One loop choosing per vertex would pay for both draws at every vertex, since
    // lavapipe runs both sides of a branch (measured: oas for 2 of 9 vertices cost as much as
    // for all 9, 3.5x the own hash's frame).
    for (; depth < MAX_DEPTH && !path.ended; ++depth) {
        VertexDims v = nextVertexDims();
        if (!fromOas(v.first, v.count)) {
            gCursor = v.first;
            break;
        }
        path = scatter(path, depth, oasDraw(v.first, v.count), v);
    }
    for (; depth < MAX_DEPTH && !path.ended; ++depth) {
        VertexDims v = nextVertexDims();
        path = scatter(path, depth, ownDraw(v.first, v.count), v);
    }
    return path.sum;
}

void main()
{
    uvec2 xy = gl_GlobalInvocationID.xy;
    if (xy.x >= params.width || xy.y >= params.height) return;
    gPixel = xy.y * params.width + xy.x;
    gPixelSeed = oas_pixel_seed(xy.x, xy.y, params.frameSeed);
    vec3 sum = vec3(0.0);
    for (uint s = 0u; s < params.samples; ++s) {
        gSample = params.firstSample + s;
        gCursor = 0u;
        uint pixelDim = next2D();  // 0
        OasDraw pixel = fromOas(pixelDim, 2u) ? oasDraw(pixelDim, 2u) : ownDraw(pixelDim, 2u);
        vec2 film = (vec2(xy) + vec2(pixel.u[0], pixel.u[1])) / vec2(params.width, params.height);
        vec3 eye = vec3(0.5, 0.5, -1.3);
        vec3 target = vec3(film.x, 1.0 - film.y, 0.0) * 0.98 + vec3(0.01, 0.01, 0.0);  // the room's open front
        sum += radiance(eye, normalize(target - eye));
    }
    sums[gPixel] += vec4(sum, float(params.samples));
}
