// Scene loading and validation (the format: scenes/README.md). The loader walks the JSON tree
// with the path of every node in hand, so each error names "file: json.path: value + valid range".
#include "scene/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>
#include <string_view>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "scene/obj.hpp"

namespace oas::scene {

namespace fs = std::filesystem;
using json = nlohmann::json;

SceneError::SceneError(std::string file, std::string jsonPath, const std::string& detail)
    : std::runtime_error(jsonPath.empty() ? fmt::format("{}: {}", file, detail)
                                          : fmt::format("{}: {}: {}", file, jsonPath, detail)),
      file_(std::move(file)),
      jsonPath_(std::move(jsonPath))
{
}

float Shape::area() const
{
    switch (type) {
    case Type::Sphere: return 4.0f * 3.14159265358979f * radius * radius;
    case Type::Quad: return glm::length(glm::cross(edgeU, edgeV));
    case Type::Triangle: return 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
    }
    return 0;
}

Aabb Shape::boundsAt(float time) const
{
    Aabb box;
    const glm::vec3 shift = velocity * time;
    switch (type) {
    case Type::Sphere:
        box.extend(center + shift - glm::vec3(radius));
        box.extend(center + shift + glm::vec3(radius));
        break;
    case Type::Quad:
        for (float a : {0.0f, 1.0f})
            for (float b : {0.0f, 1.0f}) box.extend(corner + shift + edgeU * a + edgeV * b);
        break;
    case Type::Triangle:
        box.extend(p0 + shift);
        box.extend(p1 + shift);
        box.extend(p2 + shift);
        break;
    }
    return box;
}

bool Scene::hasMotionBlur() const
{
    if (!(shutterClose > shutterOpen)) return false;
    return std::any_of(shapes.begin(), shapes.end(), [](const Shape& s) { return s.moves(); });
}

std::size_t Scene::areaLightCount() const
{
    return std::size_t(std::count_if(shapes.begin(), shapes.end(), [&](const Shape& s) { return isAreaLight(s); }));
}

int Scene::findMaterial(const std::string& materialName) const
{
    for (std::size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == materialName) return int(i);
    return -1;
}

const std::vector<std::string>& samplerNames()
{
    static const std::vector<std::string> names = {"oa",    "bose",   "bush",       "bose-bush", "addelman-kempthorne",
                                                   "cmjnd", "random", "jittered2d", "cmj2d",     "zerotwo",
                                                   "halton", "sobol"};
    return names;
}

bool samplerIsOrthogonalArray(const std::string& name)
{
    return name == "oa" || name == "bose" || name == "bush" || name == "bose-bush" || name == "addelman-kempthorne" ||
           name == "cmjnd";
}

namespace {

// ---------------------------------------------------------------------------------------------
// Helpers for messages.

constexpr std::uint32_t kMaxSpp = 1u << 24;
constexpr std::uint32_t kMaxPathDepth = 256;
constexpr std::uintmax_t kMaxSceneBytes = std::uintmax_t(64) << 20;

std::string join(std::initializer_list<std::string_view> items, std::string_view sep = ", ")
{
    std::string out;
    for (auto item : items) {
        if (!out.empty()) out += sep;
        out += item;
    }
    return out;
}

std::string join(const std::vector<std::string>& items, std::string_view sep = ", ")
{
    std::string out;
    for (const auto& item : items) {
        if (!out.empty()) out += sep;
        out += item;
    }
    return out;
}

std::string child(const std::string& path, std::string_view key)
{
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string element(const std::string& path, std::size_t index) { return fmt::format("{}[{}]", path, index); }

/// Appends a compact rendering of v to out, stopping once out holds more than `limit` characters,
/// so that a message about a huge or deeply nested value costs O(limit), not O(size) (json::dump
/// recursed through every level and crashed on deep input; parseJson also caps the depth).
void abbreviate(const json& v, std::string& out, std::size_t limit)
{
    if (out.size() > limit) return;
    if (v.is_array() || v.is_object()) {
        out += v.is_array() ? '[' : '{';
        bool first = true;
        for (auto it = v.begin(); it != v.end() && out.size() <= limit; ++it) {
            if (!first) out += ',';
            first = false;
            if (v.is_object()) out += json(it.key()).dump() + ':';
            abbreviate(*it, out, limit);
        }
        out += v.is_array() ? ']' : '}';
        return;
    }
    out += v.dump();
}

/// A JSON value for a message: numbers as numbers, strings quoted, containers abbreviated.
std::string show(const json& v)
{
    if (v.is_number_float()) return fmt::format("{}", v.get<double>());
    constexpr std::size_t kShown = 60;
    std::string text;
    abbreviate(v, text, kShown);
    if (text.size() > kShown) text = text.substr(0, kShown - 3) + "...";
    return text;
}

std::string show(const glm::vec3& v) { return fmt::format("[{}, {}, {}]", v.x, v.y, v.z); }

std::string typeName(const json& v)
{
    if (v.is_number_integer()) return "integer";
    if (v.is_number_float()) return "number";
    if (v.is_boolean()) return "boolean";
    if (v.is_string()) return "string";
    if (v.is_array()) return "array";
    if (v.is_object()) return "object";
    return "null";
}

std::size_t editDistance(std::string_view a, std::string_view b)
{
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                              std::tolower(static_cast<unsigned char>(b[j - 1]));
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (same ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

// ---------------------------------------------------------------------------------------------
// Parsing with a path tracker: duplicate keys are errors (nlohmann would keep the last silently)
// and errors inside the parser (number overflow, syntax) can name the JSON path they happened at.

struct PathTracker {
    struct Frame {
        bool object = true;
        std::string key;
        long long index = -1;
        std::set<std::string> keys;
    };
    std::vector<Frame> frames;

    std::string path(bool pendingArrayElement = false) const
    {
        std::string out;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const Frame& f = frames[i];
            if (f.object) {
                if (!f.key.empty()) out = child(out, f.key);
            } else {
                const long long idx = (pendingArrayElement && i + 1 == frames.size()) ? f.index + 1 : f.index;
                if (idx >= 0) out = element(out, std::size_t(idx));
            }
        }
        return out;
    }
};

struct DuplicateKey {
    std::string path, key;
};

/// Scene files nest a few levels (shapes[3].center); deeper input is an error, found while parsing,
/// so nothing downstream (messages, destructors) ever walks an adversarially deep tree.
constexpr std::size_t kMaxJsonDepth = 64;
struct TooDeep {
    std::string path;
};

json parseJson(const std::string& text, const std::string& file)
{
    // nlohmann's parser stops at a NUL byte as if the text ended there, so "valid JSON\0garbage"
    // would load; JSON text cannot contain a raw NUL anyway.
    if (const auto nul = text.find('\0'); nul != std::string::npos)
        throw SceneError(file, {}, fmt::format("malformed JSON: a NUL byte at offset {}: valid JSON text (UTF-8, no NUL)", nul));
    PathTracker tracker;
    auto callback = [&](int, json::parse_event_t event, json& parsed) -> bool {
        using E = json::parse_event_t;
        auto beginElement = [&] {
            if (!tracker.frames.empty() && !tracker.frames.back().object) ++tracker.frames.back().index;
        };
        switch (event) {
        case E::object_start:
        case E::array_start:
            beginElement();
            if (tracker.frames.size() >= kMaxJsonDepth) throw TooDeep{tracker.path()};
            tracker.frames.push_back({event == E::object_start, {}, -1, {}});
            break;
        case E::object_end:
        case E::array_end:
            if (!tracker.frames.empty()) tracker.frames.pop_back();
            break;
        case E::key: {
            auto& frame = tracker.frames.back();
            std::string key = parsed.get<std::string>();
            if (!frame.keys.insert(key).second) {
                frame.key.clear();
                throw DuplicateKey{tracker.path(), key};
            }
            frame.key = std::move(key);
            break;
        }
        case E::value: beginElement(); break;
        }
        return true;
    };
    try {
        return json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/false);
    } catch (const TooDeep& d) {
        throw SceneError(file, d.path,
                         fmt::format("JSON nested deeper than {} levels: valid at most {} levels of arrays and objects",
                                     kMaxJsonDepth, kMaxJsonDepth));
    } catch (const DuplicateKey& d) {
        throw SceneError(file, child(d.path, d.key), fmt::format("duplicate key \"{}\": valid each key once per object", d.key));
    } catch (const json::parse_error& e) {
        std::string why = e.what();
        if (auto pos = why.find("] "); pos != std::string::npos) why = why.substr(pos + 2);
        const std::string near = tracker.path(true);
        throw SceneError(file, {}, fmt::format("malformed JSON: {}{}", why, near.empty() ? "" : " (near " + near + ")"));
    } catch (const json::out_of_range& e) {
        // nlohmann reports 1e999 and the like as a number overflow: not a finite number.
        std::string why = e.what();
        if (auto pos = why.find("] "); pos != std::string::npos) why = why.substr(pos + 2);
        throw SceneError(file, tracker.path(true),
                         fmt::format("{}: valid finite 32-bit floats (|x| < 3.4e38)", why));
    } catch (const json::exception& e) {
        throw SceneError(file, tracker.path(true), fmt::format("malformed JSON: {}", e.what()));
    }
}

// ---------------------------------------------------------------------------------------------
// The loader.

class Loader {
public:
    Loader(std::string file, fs::path baseDir) : file_(std::move(file)), baseDir_(std::move(baseDir)) {}

    Scene load(const json& root)
    {
        Scene scene;
        objectKeys(root, "", "the scene",
                   {"version", "name", "resolution", "camera", "shutter", "environment", "materials",
                    "shapes", "lights", "integrator", "sampler"});
        if (auto* v = find(root, "version")) {
            const std::uint32_t version = integer(*v, "version", 1, 1, "1");
            (void)version;
        }
        if (auto* v = find(root, "name")) scene.name = string(*v, "name");
        resolution(require(root, "", "resolution", "[width, height], integers 1..16384"), scene);
        scene.camera = camera(require(root, "", "camera", "an object (see scenes/README.md)"));
        if (auto* v = find(root, "shutter")) shutter(*v, scene);
        if (auto* v = find(root, "environment")) scene.environment = color(*v, "environment", 0, FLT_MAX);
        materials(require(root, "", "materials", "an array of materials"), scene);
        shapes(require(root, "", "shapes", "an array of shapes"), scene);
        if (auto* v = find(root, "lights")) lights(*v, scene);
        if (auto* v = find(root, "integrator")) scene.integrator = integrator(*v);
        if (auto* v = find(root, "sampler")) scene.sampler = sampler(*v);
        return scene;
    }

private:
    [[noreturn]] void fail(const std::string& path, const std::string& detail) const
    {
        throw SceneError(file_, path, detail);
    }

    // --- structure -----------------------------------------------------------------------------

    static const json* find(const json& obj, const char* key)
    {
        auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }

    const json& require(const json& obj, const std::string& path, const char* key, std::string_view valid) const
    {
        if (auto* v = find(obj, key)) return *v;
        fail(child(path, key), fmt::format("missing (required): valid {}", valid));
    }

    /// The node must be an object whose keys are all in `allowed` ("comment" is always allowed).
    void objectKeys(const json& obj, const std::string& path, std::string_view what,
                    std::initializer_list<std::string_view> allowed) const
    {
        if (!obj.is_object())
            typeError(obj, path.empty() ? "(root)" : path, fmt::format("an object for {}", what),
                      "an object (see scenes/README.md)");
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            const std::string& key = it.key();
            if (key == "comment") {
                if (!it.value().is_string()) typeError(it.value(), child(path, key), "a string", "any text (ignored)");
                continue;
            }
            if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
            std::string hint;
            for (auto candidate : allowed)
                if (editDistance(key, candidate) <= 2) hint = fmt::format(" (did you mean \"{}\"?)", candidate);
            fail(child(path, key), fmt::format("unknown key \"{}\" in {}{}: valid keys are {}, comment", key, what, hint,
                                               join(allowed)));
        }
    }

    // --- scalars -------------------------------------------------------------------------------

    [[noreturn]] void typeError(const json& v, const std::string& path, std::string_view expected,
                                std::string_view valid) const
    {
        fail(path, fmt::format("expected {}, got {} {}: valid {}", expected, typeName(v), show(v), valid));
    }

    /// A finite number that is also finite as a 32-bit float.
    float real(const json& v, const std::string& path, std::string_view valid = "any finite number") const
    {
        if (!v.is_number()) typeError(v, path, "a number", valid);
        const double d = v.get<double>();
        if (!std::isfinite(d) || std::fabs(d) > double(FLT_MAX))
            fail(path, fmt::format("{} is not a finite 32-bit float: valid |x| < 3.4e38", show(v)));
        return float(d);
    }

    /// A number in [lo, hi] (open ends where loOpen / hiOpen); `valid` describes the range.
    float realIn(const json& v, const std::string& path, double lo, double hi, std::string_view valid,
                 bool loOpen = false, bool hiOpen = false) const
    {
        const float f = real(v, path, valid);
        const bool ok = (loOpen ? f > lo : f >= lo) && (hiOpen ? f < hi : f <= hi);
        if (!ok) fail(path, fmt::format("{} is out of range: valid {}", show(v), valid));
        return f;
    }

    std::uint32_t integer(const json& v, const std::string& path, std::uint32_t lo, std::uint32_t hi,
                          std::string_view valid) const
    {
        if (!v.is_number()) typeError(v, path, "an integer", valid);
        double d;
        if (v.is_number_unsigned())
            d = double(v.get<std::uint64_t>());
        else if (v.is_number_integer())
            d = double(v.get<std::int64_t>());
        else {
            d = v.get<double>();
            if (!std::isfinite(d) || d != std::floor(d))
                fail(path, fmt::format("expected an integer, got {}: valid {}", show(v), valid));
        }
        if (d < lo || d > hi) fail(path, fmt::format("{} is out of range: valid {}", show(v), valid));
        return std::uint32_t(d);
    }

    bool boolean(const json& v, const std::string& path) const
    {
        if (!v.is_boolean()) typeError(v, path, "a boolean", "true | false");
        return v.get<bool>();
    }

    std::string string(const json& v, const std::string& path, std::string_view valid = "a string") const
    {
        if (!v.is_string()) typeError(v, path, "a string", valid);
        return v.get<std::string>();
    }

    std::string choice(const json& v, const std::string& path, std::initializer_list<std::string_view> valid,
                       std::string_view extraHint = {}) const
    {
        const std::string s = string(v, path, join(valid, " | "));
        if (std::find(valid.begin(), valid.end(), s) == valid.end())
            fail(path, fmt::format("\"{}\" is not valid: valid {}{}", s, join(valid, " | "), extraHint));
        return s;
    }

    // --- vectors -------------------------------------------------------------------------------

    glm::vec3 vec3(const json& v, const std::string& path) const
    {
        if (!v.is_array() || v.size() != 3) typeError(v, path, "[x, y, z]", "3 finite numbers");
        return {real(v[0], element(path, 0)), real(v[1], element(path, 1)), real(v[2], element(path, 2))};
    }

    /// A colour: one number (grey) or [r, g, b], each component in [lo, hi].
    glm::vec3 color(const json& v, const std::string& path, float lo, float hi) const
    {
        const std::string valid = hi == FLT_MAX ? fmt::format(">= {}", lo) : fmt::format("{} .. {}", lo, hi);
        auto component = [&](const json& c, const std::string& p) {
            const float f = real(c, p, valid);
            if (!(f >= lo && f <= hi)) fail(p, fmt::format("{} is out of range: valid {}", show(c), valid));
            return f;
        };
        if (v.is_number()) {
            const float g = component(v, path);
            return {g, g, g};
        }
        if (!v.is_array() || v.size() != 3)
            typeError(v, path, "a colour", fmt::format("one number or [r, g, b], each {}", valid));
        return {component(v[0], element(path, 0)), component(v[1], element(path, 1)), component(v[2], element(path, 2))};
    }

    /// v / |v| with the length taken in double: in float, |v| of a huge vector overflows and
    /// normalize() returns zeros (a spot direction of [3e38, 3e38, 3e38] became [0, 0, 0]).
    static glm::vec3 unitVector(const glm::vec3& v)
    {
        const double len = std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z);
        return glm::vec3(float(v.x / len), float(v.y / len), float(v.z / len));
    }

    glm::vec3 nonzeroVec3(const json& v, const std::string& path, std::string_view what) const
    {
        const glm::vec3 r = vec3(v, path);
        if (!(glm::length(r) > 0)) fail(path, fmt::format("{} {} has zero length: valid nonzero {}", what, show(r), what));
        return r;
    }

    // --- sections ------------------------------------------------------------------------------

    void resolution(const json& v, Scene& scene) const
    {
        if (!v.is_array() || v.size() != 2) typeError(v, "resolution", "[width, height]", "two integers 1 .. 16384");
        scene.width = integer(v[0], "resolution[0]", 1, kMaxResolution, "1 .. 16384 pixels");
        scene.height = integer(v[1], "resolution[1]", 1, kMaxResolution, "1 .. 16384 pixels");
    }

    Camera camera(const json& v) const
    {
        const std::string p = "camera";
        objectKeys(v, p, "the camera",
                   {"type", "position", "lookAt", "up", "fovY", "apertureRadius", "focusDistance"});
        Camera cam;
        std::string type;
        if (auto* t = find(v, "type")) type = choice(*t, child(p, "type"), {"pinhole", "thinlens"});
        cam.position = vec3(require(v, p, "position", "[x, y, z]"), child(p, "position"));
        cam.lookAt = vec3(require(v, p, "lookAt", "[x, y, z], a point other than position"), child(p, "lookAt"));
        const glm::vec3 axis = cam.lookAt - cam.position;
        if (!(glm::length(axis) > 0))
            fail(child(p, "lookAt"), fmt::format("{} equals the camera position: valid any other point", show(cam.lookAt)));
        if (!std::isfinite(glm::length(axis)))
            fail(child(p, "lookAt"), fmt::format("lookAt {} - position {} overflows 32-bit floats (|lookAt - position| "
                                                 "must be < 3.4e38): valid closer points",
                                                 show(cam.lookAt), show(cam.position)));
        if (auto* u = find(v, "up")) cam.up = vec3(*u, child(p, "up"));
        // Written so that NaN (an up vector whose length overflows) fails too.
        if (!(glm::length(cam.up) > 0 && std::isfinite(glm::length(cam.up))) ||
            !(glm::length(glm::cross(glm::normalize(axis), glm::normalize(cam.up))) >= 1e-6f))
            fail(child(p, "up"), fmt::format("{} is zero, too long for 32-bit floats, or parallel to the view direction {}: valid a vector not "
                                             "parallel to lookAt - position",
                                             show(cam.up), show(axis)));
        cam.fovYDegrees = realIn(require(v, p, "fovY", "degrees in (0, 180)"), child(p, "fovY"), 0, 180,
                                 "(0, 180) degrees (full vertical angle)", true, true);
        if (auto* a = find(v, "apertureRadius"))
            cam.apertureRadius = realIn(*a, child(p, "apertureRadius"), 0, FLT_MAX, ">= 0 (world units; 0 = pinhole)");
        if (type == "pinhole" && cam.apertureRadius > 0)
            fail(child(p, "apertureRadius"), fmt::format("{} on a pinhole camera: valid 0 for \"pinhole\" (use type "
                                                         "\"thinlens\" for depth of field)",
                                                         cam.apertureRadius));
        if (type == "thinlens" && !(cam.apertureRadius > 0))
            fail(child(p, "apertureRadius"),
                 fmt::format("{} on a thin-lens camera: valid > 0 (world units; use type \"pinhole\" for none)",
                             cam.apertureRadius));
        cam.thinLens = cam.apertureRadius > 0;
        cam.focusDistance = glm::length(axis);
        if (auto* f = find(v, "focusDistance"))
            cam.focusDistance = realIn(*f, child(p, "focusDistance"), 0, FLT_MAX, "> 0 (world units)", true);
        return cam;
    }

    void shutter(const json& v, Scene& scene) const
    {
        objectKeys(v, "shutter", "the shutter", {"open", "close"});
        if (auto* o = find(v, "open")) scene.shutterOpen = real(*o, "shutter.open");
        if (auto* c = find(v, "close")) scene.shutterClose = real(*c, "shutter.close");
        if (scene.shutterClose < scene.shutterOpen)
            fail("shutter.close", fmt::format("{} is before shutter.open {}: valid close >= open", scene.shutterClose,
                                              scene.shutterOpen));
    }

    void materials(const json& v, Scene& scene) const
    {
        if (!v.is_array()) typeError(v, "materials", "an array", "an array of material objects");
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string p = element("materials", i);
            const json& m = v[i];
            if (!m.is_object()) typeError(m, p, "an object", "a material object");
            Material mat;
            std::string type = "diffuse";
            if (auto* t = find(m, "type")) type = choice(*t, child(p, "type"), {"diffuse", "conductor", "dielectric"});
            if (type == "diffuse") {
                mat.type = Material::Type::Diffuse;
                objectKeys(m, p, "a diffuse material", {"name", "type", "albedo", "emission"});
                mat.albedo = glm::vec3(0.8f);
            } else if (type == "conductor") {
                mat.type = Material::Type::Conductor;
                objectKeys(m, p, "a conductor material", {"name", "type", "albedo", "roughness", "emission"});
                mat.albedo = glm::vec3(0.9f);
            } else {
                mat.type = Material::Type::Dielectric;
                objectKeys(m, p, "a dielectric material", {"name", "type", "albedo", "roughness", "ior", "emission"});
                mat.albedo = glm::vec3(1.0f);
            }
            mat.name = string(require(m, p, "name", "a unique non-empty string"), child(p, "name"));
            if (mat.name.empty()) fail(child(p, "name"), "\"\" is not valid: valid a unique non-empty string");
            if (int prev = scene.findMaterial(mat.name); prev >= 0)
                fail(child(p, "name"), fmt::format("\"{}\" is already the name of materials[{}]: valid a unique name",
                                                   mat.name, prev));
            if (auto* a = find(m, "albedo")) mat.albedo = color(*a, child(p, "albedo"), 0, 1);
            if (auto* r = find(m, "roughness"))
                mat.roughness = realIn(*r, child(p, "roughness"), 0, 1, "0 .. 1 (GGX alpha; 0 = smooth)");
            if (auto* n = find(m, "ior")) mat.ior = realIn(*n, child(p, "ior"), 1, 4, "1 .. 4 (index of refraction)");
            if (auto* e = find(m, "emission")) mat.emission = color(*e, child(p, "emission"), 0, FLT_MAX);
            scene.materials.push_back(std::move(mat));
        }
    }

    std::uint32_t materialRef(const json& shape, const std::string& p, const Scene& scene) const
    {
        const std::string key = child(p, "material");
        const std::string name = string(require(shape, p, "material", "the name of a material"), key);
        const int index = scene.findMaterial(name);
        if (index < 0) {
            std::vector<std::string> names;
            for (const auto& m : scene.materials) names.push_back("\"" + m.name + "\"");
            fail(key, fmt::format("material \"{}\" is not defined: valid {}", name,
                                  names.empty() ? std::string("(no materials defined)") : join(names)));
        }
        return std::uint32_t(index);
    }

    void shapes(const json& v, Scene& scene)
    {
        if (!v.is_array()) typeError(v, "shapes", "an array", "an array of shape objects");
        if (v.empty()) fail("shapes", "[] is empty: valid at least one shape");
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string p = element("shapes", i);
            const json& s = v[i];
            if (!s.is_object()) typeError(s, p, "an object", "a shape object");
            const std::string type = choice(require(s, p, "type", "sphere | quad | rectangle | triangle | mesh"),
                                            child(p, "type"), {"sphere", "quad", "rectangle", "triangle", "mesh"});
            if (type == "mesh") {
                mesh(s, p, scene);
                continue;
            }
            Shape shape;
            if (type == "sphere") {
                objectKeys(s, p, "a sphere", {"type", "material", "center", "radius", "velocity"});
                shape.type = Shape::Type::Sphere;
                shape.center = vec3(require(s, p, "center", "[x, y, z]"), child(p, "center"));
                shape.radius = realIn(require(s, p, "radius", "> 0 (world units)"), child(p, "radius"), 0, FLT_MAX,
                                      "> 0 (world units)", true);
            } else if (type == "quad" || type == "rectangle") {
                objectKeys(s, p, "a " + type, {"type", "material", "corner", "edgeU", "edgeV", "velocity"});
                shape.type = Shape::Type::Quad;
                shape.corner = vec3(require(s, p, "corner", "[x, y, z]"), child(p, "corner"));
                shape.edgeU = vec3(require(s, p, "edgeU", "[x, y, z], nonzero"), child(p, "edgeU"));
                shape.edgeV = vec3(require(s, p, "edgeV", "[x, y, z], nonzero, not parallel to edgeU"), child(p, "edgeV"));
            } else {
                objectKeys(s, p, "a triangle", {"type", "material", "p0", "p1", "p2", "velocity"});
                shape.type = Shape::Type::Triangle;
                shape.p0 = vec3(require(s, p, "p0", "[x, y, z]"), child(p, "p0"));
                shape.p1 = vec3(require(s, p, "p1", "[x, y, z]"), child(p, "p1"));
                shape.p2 = vec3(require(s, p, "p2", "[x, y, z]"), child(p, "p2"));
            }
            shape.material = materialRef(s, p, scene);
            if (auto* vel = find(s, "velocity")) shape.velocity = vec3(*vel, child(p, "velocity"));
            const bool light = scene.materials[shape.material].emits();
            const std::string kind = light ? "area light" : "shape";
            if (shape.type == Shape::Type::Quad && isDegenerateParallelogram(shape.edgeU, shape.edgeV))
                fail(child(p, "edgeV"),
                     fmt::format("zero-area {}: edgeU {} and edgeV {} are zero or parallel (area {}): valid "
                                 "non-parallel nonzero edges, area > 0",
                                 kind, show(shape.edgeU), show(shape.edgeV), shape.area()));
            if (shape.type == Shape::Type::Triangle && isDegenerateTriangle(shape.p0, shape.p1, shape.p2))
                fail(p, fmt::format("zero-area {}: triangle p0 {} p1 {} p2 {} (area {}): valid non-collinear points, "
                                    "area > 0",
                                    kind, show(shape.p0), show(shape.p1), show(shape.p2), shape.area()));
            if (!std::isfinite(shape.area()))
                fail(p, fmt::format("the {}'s area {} overflows 32-bit floats: valid a smaller shape", kind, shape.area()));
            checkFiniteBounds(shape, scene, p, kind);
            scene.shapes.push_back(std::move(shape));
        }
    }

    /// The renderer bounds a shape at shutter open and close; a velocity that carries it past the
    /// float range there would give infinite or NaN boxes (the loader checked positions at t = 0).
    void checkFiniteBounds(const Shape& shape, const Scene& scene, const std::string& path, std::string_view kind) const
    {
        for (const float t : {0.0f, scene.shutterOpen, scene.shutterClose}) {
            const Aabb box = shape.boundsAt(t);
            const bool finite = std::isfinite(box.lo.x) && std::isfinite(box.lo.y) && std::isfinite(box.lo.z) &&
                                std::isfinite(box.hi.x) && std::isfinite(box.hi.y) && std::isfinite(box.hi.z);
            if (!finite)
                fail(path, fmt::format("the {} moved by velocity {} to time {} leaves the 32-bit float range: valid a "
                                       "smaller velocity or shutter interval",
                                       kind, show(shape.velocity), t));
        }
    }

    void mesh(const json& s, const std::string& p, Scene& scene) const
    {
        objectKeys(s, p, "a mesh", {"type", "material", "file", "translate", "scale", "velocity"});
        MeshInfo info;
        info.file = string(require(s, p, "file", "an OBJ file path (relative to the scene file)"), child(p, "file"));
        if (info.file.empty()) fail(child(p, "file"), "\"\" is not valid: valid an OBJ file path");
        const std::uint32_t material = materialRef(s, p, scene);
        glm::vec3 translate(0), scale(1), velocity(0);
        if (auto* t = find(s, "translate")) translate = vec3(*t, child(p, "translate"));
        if (auto* sc = find(s, "scale")) {
            const std::string sp = child(p, "scale");
            if (sc->is_number())
                scale = glm::vec3(real(*sc, sp));
            else if (sc->is_array())
                scale = vec3(*sc, sp);
            else
                typeError(*sc, sp, "a number or [sx, sy, sz]", "nonzero finite factors");
            if (scale.x == 0 || scale.y == 0 || scale.z == 0)
                fail(sp, fmt::format("{} has a zero factor: valid nonzero factors (negative mirrors)", show(*sc)));
        }
        if (auto* vel = find(s, "velocity")) velocity = vec3(*vel, child(p, "velocity"));

        const fs::path given(info.file);
        info.resolved = given.is_absolute() ? given : baseDir_ / given;
        ObjMesh obj;
        try {
            obj = readObj(info.resolved);
        } catch (const ObjError& e) {
            fail(child(p, "file"),
                 e.line() ? fmt::format("cannot load mesh \"{}\": {}", info.file, e.what())
                          : fmt::format("cannot load mesh \"{}\": {}: valid a readable OBJ file (relative paths start "
                                        "at the scene file's directory)",
                                        info.file, e.what()));
        }
        info.firstShape = scene.shapes.size();
        info.degenerateDropped = obj.degenerateDropped;
        for (const auto& tri : obj.triangles) {
            Shape shape;
            shape.type = Shape::Type::Triangle;
            shape.material = material;
            shape.p0 = obj.positions[tri[0]] * scale + translate;
            shape.p1 = obj.positions[tri[1]] * scale + translate;
            shape.p2 = obj.positions[tri[2]] * scale + translate;
            const auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
            if (!finite(shape.p0) || !finite(shape.p1) || !finite(shape.p2))
                fail(child(p, "scale"), fmt::format("mesh \"{}\" scaled by {} and translated by {} leaves the 32-bit "
                                                    "float range: valid a smaller scale or translation",
                                                    info.file, show(scale), show(translate)));
            if (isDegenerateTriangle(shape.p0, shape.p1, shape.p2)) {
                ++info.degenerateDropped;
                continue;
            }
            if (!std::isfinite(shape.area()))
                fail(child(p, "scale"), fmt::format("mesh \"{}\" scaled by {} has a triangle whose area {} overflows 32-bit "
                                                    "floats: valid a smaller scale",
                                                    info.file, show(scale), shape.area()));
            shape.velocity = velocity;
            checkFiniteBounds(shape, scene, child(p, "velocity"), "mesh triangle");
            shape.sourceMesh = info.file;
            scene.shapes.push_back(std::move(shape));
        }
        info.triangles = scene.shapes.size() - info.firstShape;
        if (info.triangles == 0)
            fail(child(p, "file"), fmt::format("mesh \"{}\" has no triangles of nonzero area ({} faces, {} zero-area "
                                               "triangles dropped): valid a mesh with at least one triangle",
                                               info.file, obj.faces, info.degenerateDropped));
        scene.meshes.push_back(std::move(info));
    }

    void lights(const json& v, Scene& scene) const
    {
        if (!v.is_array()) typeError(v, "lights", "an array", "an array of light objects");
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string p = element("lights", i);
            const json& l = v[i];
            if (!l.is_object()) typeError(l, p, "an object", "a light object");
            const std::string type =
                choice(require(l, p, "type", "point | spot"), child(p, "type"), {"point", "spot"},
                       " (area lights are shapes whose material has \"emission\"; a constant environment is the "
                       "top-level \"environment\")");
            Light light;
            if (type == "point") {
                objectKeys(l, p, "a point light", {"type", "position", "intensity"});
                light.type = Light::Type::Point;
            } else {
                objectKeys(l, p, "a spot light",
                           {"type", "position", "intensity", "direction", "outerAngle", "innerAngle"});
                light.type = Light::Type::Spot;
            }
            light.position = vec3(require(l, p, "position", "[x, y, z]"), child(p, "position"));
            light.intensity = color(require(l, p, "intensity", "W/sr, a number or [r, g, b] >= 0"),
                                    child(p, "intensity"), 0, FLT_MAX);
            if (light.type == Light::Type::Spot) {
                light.direction = unitVector(
                    nonzeroVec3(require(l, p, "direction", "[x, y, z], nonzero"), child(p, "direction"), "direction"));
                const float outer = realIn(require(l, p, "outerAngle", "degrees in (0, 180]"), child(p, "outerAngle"), 0,
                                           180, "(0, 180] degrees (half-angle from the axis)", true);
                float inner = outer;
                if (auto* in = find(l, "innerAngle"))
                    inner = realIn(*in, child(p, "innerAngle"), 0, outer,
                                   fmt::format("0 .. outerAngle = {} degrees (half-angle from the axis)", outer));
                constexpr double kDegree = 3.14159265358979323846 / 180.0;
                light.cosOuter = float(std::cos(double(outer) * kDegree));
                light.cosInner = float(std::cos(double(inner) * kDegree));
            }
            scene.lights.push_back(light);
        }
    }

    Integrator integrator(const json& v) const
    {
        const std::string p = "integrator";
        if (!v.is_object()) typeError(v, p, "an object", "an integrator object");
        Integrator it;
        std::string type = "path";
        if (auto* t = find(v, "type")) type = choice(*t, child(p, "type"), {"direct", "path"});
        if (type == "direct") {
            objectKeys(v, p, "a direct-lighting integrator", {"type", "maxDepth", "nextEventEstimation", "mis"});
            it.type = Integrator::Type::Direct;
            it.maxDepth = 1;
            if (auto* d = find(v, "maxDepth")) it.maxDepth = integer(*d, child(p, "maxDepth"), 1, 1, "1 for direct lighting");
        } else {
            objectKeys(v, p, "a path integrator",
                       {"type", "maxDepth", "nextEventEstimation", "mis", "rouletteStartDepth"});
            it.type = Integrator::Type::Path;
            if (auto* d = find(v, "maxDepth"))
                it.maxDepth = integer(*d, child(p, "maxDepth"), 1, kMaxPathDepth, "1 .. 256 scattering vertices");
            if (auto* r = find(v, "rouletteStartDepth"))
                it.rouletteStartDepth = integer(*r, child(p, "rouletteStartDepth"), 0, it.maxDepth,
                                                fmt::format("0 (never) .. maxDepth = {}", it.maxDepth));
        }
        if (auto* n = find(v, "nextEventEstimation")) it.nextEventEstimation = boolean(*n, child(p, "nextEventEstimation"));
        it.mis = it.nextEventEstimation;
        if (auto* m = find(v, "mis")) {
            it.mis = boolean(*m, child(p, "mis"));
            if (it.mis && !it.nextEventEstimation)
                fail(child(p, "mis"), "true without next-event estimation: valid false when nextEventEstimation is false "
                                      "(MIS weighs light sampling against BSDF sampling)");
        }
        return it;
    }

    SamplerSpec sampler(const json& v) const
    {
        const std::string p = "sampler";
        objectKeys(v, p, "the sampler", {"name", "spp", "offset", "strength", "seed"});
        SamplerSpec spec;
        if (auto* n = find(v, "name")) {
            spec.name = string(*n, child(p, "name"));
            const auto& names = samplerNames();
            if (std::find(names.begin(), names.end(), spec.name) == names.end())
                fail(child(p, "name"), fmt::format("\"{}\" is not a sampler: valid {}", spec.name, join(names, " | ")));
        }
        spec.spp = integer(require(v, p, "spp", "1 .. 16777216 samples per pixel"), child(p, "spp"), 1, kMaxSpp,
                           "1 .. 16777216 (2^24) samples per pixel");
        const bool oa = samplerIsOrthogonalArray(spec.name);
        if (auto* o = find(v, "offset")) {
            if (!oa)
                fail(child(p, "offset"), fmt::format("{} given for sampler \"{}\", which is not an orthogonal array: "
                                                     "valid only with oa, bose, bush, bose-bush, addelman-kempthorne, cmjnd",
                                                     show(*o), spec.name));
            spec.offset = choice(*o, child(p, "offset"), {"centered", "j", "mj", "cmj"});
        }
        if (auto* s = find(v, "strength")) {
            if (!oa)
                fail(child(p, "strength"), fmt::format("{} given for sampler \"{}\", which is not an orthogonal array: "
                                                       "valid only with oa, bose, bush, bose-bush, addelman-kempthorne, cmjnd",
                                                       show(*s), spec.name));
            const bool twoOnly = spec.name == "bose" || spec.name == "bose-bush" || spec.name == "addelman-kempthorne";
            spec.strength = twoOnly ? integer(*s, child(p, "strength"), 0, 2,
                                              fmt::format("0 (default) or 2: {} has strength 2 only", spec.name))
                                    : integer(*s, child(p, "strength"), 0, 24, "0 (the sampler's default) or 2 .. 24");
            if (spec.strength == 1)
                fail(child(p, "strength"), "1 is out of range: valid 0 (the sampler's default) or 2 .. 24");
        }
        if (auto* s = find(v, "seed")) spec.seed = integer(*s, child(p, "seed"), 0, 0xffffffffu, "0 .. 4294967295");
        return spec;
    }

    std::string file_;
    fs::path baseDir_;
};

}  // namespace

Scene parseScene(const std::string& jsonText, const fs::path& nameForMessages, const fs::path& baseDir)
{
    const std::string file = nameForMessages.string();
    const json root = parseJson(jsonText, file);
    Scene scene = Loader(file, baseDir).load(root);
    scene.path = nameForMessages;
    if (scene.name.empty()) scene.name = nameForMessages.stem().string();
    return scene;
}

Scene loadScene(const fs::path& file)
{
    std::error_code ec;
    const auto status = fs::status(file, ec);
    if (!fs::exists(status)) throw SceneError(file.string(), {}, "scene file not found (no such file)");
    if (fs::is_directory(status)) throw SceneError(file.string(), {}, "is a directory, not a scene file");
    // A device or FIFO (/dev/zero, a pipe) would be read without end or block forever.
    if (!fs::is_regular_file(status))
        throw SceneError(file.string(), {}, "is not a regular file (a device, FIFO or socket): valid a scene file");
    if (const auto size = fs::file_size(file, ec); !ec && size > kMaxSceneBytes)
        throw SceneError(file.string(), {}, fmt::format("is {} bytes: valid scene files up to {} MiB (meshes go in OBJ files)",
                                                        size, kMaxSceneBytes >> 20));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw SceneError(file.string(), {}, "cannot open the scene file for reading");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw SceneError(file.string(), {}, "error reading the scene file");
    fs::path base = file.parent_path();
    if (base.empty()) base = ".";
    return parseScene(text.str(), file, base);
}

std::string summary(const Scene& scene)
{
    std::string effects;
    auto add = [&](std::string_view e) {
        if (!effects.empty()) effects += ", ";
        effects += e;
    };
    add(scene.hasDepthOfField() ? "thin lens" : "pinhole");
    if (scene.hasMotionBlur()) add(fmt::format("motion blur [{}, {}]", scene.shutterOpen, scene.shutterClose));
    std::size_t triangles = 0;
    for (const auto& m : scene.meshes) triangles += m.triangles;
    const auto& it = scene.integrator;
    const std::string integrator =
        it.type == Integrator::Type::Direct
            ? std::string("direct lighting")
            : fmt::format("path tracing maxDepth {}{}{}{}", it.maxDepth, it.nextEventEstimation ? " NEE" : "",
                          it.mis ? "+MIS" : "",
                          it.rouletteStartDepth ? fmt::format(" RR from {}", it.rouletteStartDepth) : std::string());
    std::string sampler = fmt::format("{} {} spp", scene.sampler.name, scene.sampler.spp);
    if (samplerIsOrthogonalArray(scene.sampler.name)) sampler += " " + scene.sampler.offset;
    return fmt::format("{}: {}x{}, {}; {} shapes ({} mesh triangles), {} materials, {} area lights, {} point/spot "
                       "lights{}; {}; sampler {}",
                       scene.name, scene.width, scene.height, effects, scene.shapes.size(), triangles,
                       scene.materials.size(), scene.areaLightCount(), scene.lights.size(),
                       scene.hasEnvironment() ? ", environment" : "", integrator, sampler);
}

}  // namespace oas::scene
