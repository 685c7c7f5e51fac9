#pragma once
// Scene description: the data model a renderer consumes, and the JSON loader (format documented
// field by field in scenes/README.md). Everything is validated at load time; a bad scene throws
// SceneError naming the file, the JSON path of the offending field, the bad value and the valid
// range, e.g. "cornell.json: shapes[2].radius: -1 is out of range: valid > 0 (world units)".
//
// Conventions: right-handed world space, any unit of length ("world units"), colours are linear
// RGB. Time is the same unit as the shutter interval; a shape's stated position is its position
// at time t = 0 and it moves as position(t) = position + velocity * t.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/bvh.hpp"

namespace oas::scene {

/// The largest image side a scene (its "resolution") or a command-line override may ask for.
inline constexpr std::uint32_t kMaxResolution = 16384;

/// A scene that cannot be loaded. what() is the complete message; the parts are kept for tools
/// and tests. jsonPath() is empty when the problem is not in one field (unreadable file, JSON
/// syntax error: then the message carries line and column instead).
class SceneError : public std::runtime_error {
public:
    SceneError(std::string file, std::string jsonPath, const std::string& detail);
    const std::string& file() const { return file_; }
    const std::string& jsonPath() const { return jsonPath_; }

private:
    std::string file_, jsonPath_;
};

/// Pinhole or thin-lens camera. The image's vertical axis is `up` projected perpendicular to the
/// view direction; image x points along normalize(cross(lookAt - position, up)) (to the right);
/// pixel (0, 0) is the top-left corner. Aspect ratio = width / height.
struct Camera {
    bool thinLens = false;        ///< true exactly when apertureRadius > 0
    glm::vec3 position{0, 0, 0};  ///< eye / lens centre, world units
    glm::vec3 lookAt{0, 0, -1};   ///< a point on the view axis, world units
    glm::vec3 up{0, 1, 0};        ///< not parallel to the view axis; need not be unit length
    float fovYDegrees = 40;       ///< full vertical field of view, degrees, in (0, 180)
    float apertureRadius = 0;     ///< lens radius, world units; 0 = pinhole
    float focusDistance = 1;      ///< distance along the view axis that is in focus (> 0)
};

/// A surface material. Every material may emit: nonzero emission makes its shapes area lights,
/// emitting on the front side only (the side the geometric normal points to, see Shape).
struct Material {
    enum class Type { Diffuse, Conductor, Dielectric };
    Type type = Type::Diffuse;
    /// Diffuse: reflectance in [0,1]. Conductor: F0 (normal-incidence reflectance, Schlick) in
    /// [0,1]. Dielectric: tint multiplying reflection and transmission, in [0,1].
    glm::vec3 albedo{0.8f, 0.8f, 0.8f};
    float roughness = 0;          ///< GGX alpha for conductor/dielectric, [0,1]; 0 = smooth
    float ior = 1.5f;             ///< dielectric: index of refraction inside / outside
    glm::vec3 emission{0, 0, 0};  ///< emitted radiance (W sr^-1 m^-2 per channel), >= 0
    std::string name;             ///< unique; shapes refer to materials by name

    bool emits() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

/// A primitive. Geometric normals (which side an emitter lights): sphere outward; quad
/// normalize(cross(edgeU, edgeV)); triangle normalize(cross(p1 - p0, p2 - p0)). Surfaces scatter
/// light on both sides.
struct Shape {
    enum class Type { Sphere, Quad, Triangle };
    Type type = Type::Sphere;
    std::uint32_t material = 0;  ///< index into Scene::materials
    // Sphere.
    glm::vec3 center{0, 0, 0};
    float radius = 0;  ///< > 0
    // Quad: the parallelogram corner + a*edgeU + b*edgeV, a, b in [0,1] (a rectangle when the
    // edges are perpendicular). Area = |cross(edgeU, edgeV)| > 0.
    glm::vec3 corner{0, 0, 0}, edgeU{0, 0, 0}, edgeV{0, 0, 0};
    // Triangle (also every triangle of a mesh, in world space). Area > 0.
    glm::vec3 p0{0, 0, 0}, p1{0, 0, 0}, p2{0, 0, 0};
    /// Linear motion, world units per unit time: position(t) = position + velocity * t.
    glm::vec3 velocity{0, 0, 0};
    /// Mesh file as written in the scene (triangles expanded from a mesh), else empty.
    std::string sourceMesh;

    bool moves() const { return velocity.x != 0 || velocity.y != 0 || velocity.z != 0; }
    /// Surface area in world units squared (at t = 0; motion is a translation).
    float area() const;
    /// The box the renderer bounds the shape by at `time` (positions + velocity * time, in float
    /// as the renderer computes them). The loader refuses shapes whose box is not finite.
    Aabb boundsAt(float time) const;
};

/// A delta light (not hit by rays; sampled by next-event estimation only).
struct Light {
    enum class Type { Point, Spot };
    Type type = Type::Point;
    glm::vec3 position{0, 0, 0};    ///< world units
    glm::vec3 intensity{0, 0, 0};   ///< radiant intensity, W/sr per channel, >= 0
    glm::vec3 direction{0, -1, 0};  ///< spot: unit axis of the cone
    /// Spot: cosines of the outer and inner half-angles (cosOuter <= cosInner). Full intensity
    /// inside the inner cone, zero outside the outer cone, smoothstep in between.
    float cosOuter = -1, cosInner = -1;
};

struct Integrator {
    enum class Type { Direct, Path };
    Type type = Type::Path;
    /// Path vertices (surface hits) after the camera: x1 .. x_maxDepth. With next-event estimation
    /// every vertex samples the lights, so paths scattering up to maxDepth times count (direct
    /// lighting = 1). Without NEE lights are found only by hitting them and the last vertex only
    /// collects emission: paths scatter up to maxDepth - 1 times.
    std::uint32_t maxDepth = 5;
    bool nextEventEstimation = true;       ///< sample lights explicitly at each vertex
    bool mis = true;                       ///< with NEE: weight light and BSDF sampling (power heuristic)
    std::uint32_t rouletteStartDepth = 0;  ///< Russian roulette from this vertex on; 0 = never
};

/// The sampler request (the names and rules of oas::PatternRequest, host/oas/pattern.hpp).
/// Whether spp can be made exactly by the chosen construction is checked when rendering, once
/// the dimension count is known.
struct SamplerSpec {
    std::string name = "oa";     ///< "oa" (the chooser) or one of oas::samplerNames()
    std::uint32_t spp = 16;      ///< samples per pixel, 1 .. 2^24
    std::string offset = "cmj";  ///< centered | j | mj | cmj (orthogonal arrays only)
    std::uint32_t strength = 0;  ///< 0 = the sampler's default, else 2 .. 24
    std::uint32_t seed = 0;      ///< user seed mixed into every pixel seed
};

/// One mesh entry of the scene file, after expansion into Scene::shapes.
struct MeshInfo {
    std::string file;                ///< as written in the scene
    std::filesystem::path resolved;  ///< the file that was read
    std::size_t firstShape = 0;      ///< its triangles are shapes[firstShape, firstShape + triangles)
    std::size_t triangles = 0;
    std::size_t degenerateDropped = 0;  ///< zero-area triangles left out (in the file or after scaling)
};

struct Scene {
    std::uint32_t width = 0, height = 0;  ///< image size in pixels, 1 .. 16384 each
    Camera camera;
    float shutterOpen = 0, shutterClose = 0;  ///< time interval sampled per camera ray
    std::vector<Material> materials;
    std::vector<Shape> shapes;
    std::vector<Light> lights;
    glm::vec3 environment{0, 0, 0};  ///< constant radiance arriving from every direction; 0 = none
    Integrator integrator;
    SamplerSpec sampler;
    std::vector<MeshInfo> meshes;
    std::string name;            ///< "name" in the file, else the file's stem
    std::filesystem::path path;  ///< the scene file (for messages and relative paths)

    /// The shutter is open for a nonzero time and some shape moves: time is a sample dimension.
    bool hasMotionBlur() const;
    /// Thin-lens camera: the lens position is a 2D sample dimension.
    bool hasDepthOfField() const { return camera.apertureRadius > 0; }
    /// Shapes whose material emits (every triangle of an emitting mesh counts).
    std::size_t areaLightCount() const;
    bool isAreaLight(const Shape& shape) const { return materials[shape.material].emits(); }
    bool hasEnvironment() const { return environment.x > 0 || environment.y > 0 || environment.z > 0; }
    /// Index of the material with this name, or -1.
    int findMaterial(const std::string& name) const;
};

/// Reads and validates a scene file; mesh paths are relative to the file's directory.
Scene loadScene(const std::filesystem::path& file);
/// The same from text: nameForMessages prefixes messages and becomes Scene::path; mesh paths are
/// relative to baseDir.
Scene parseScene(const std::string& jsonText, const std::filesystem::path& nameForMessages, const std::filesystem::path& baseDir);

/// The names accepted in "sampler.name" ("oa" first), and whether each is an orthogonal array
/// (takes "offset" and "strength"). From the C builder's table (host/oas/oas_pattern.h), as oas::samplerNames().
const std::vector<std::string>& samplerNames();
bool samplerIsOrthogonalArray(const std::string& name);

/// One line per scene: size, effects, counts. For logs.
std::string summary(const Scene& scene);

}  // namespace oas::scene
