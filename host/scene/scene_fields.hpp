#pragma once
// Internal to host/scene: reading JSON fields so that every refusal is a SceneError naming the
// file, the JSON path of the field, the value and the valid range (scenes/README.md). The loader's
// sections (scene_loader.hpp) read the file through these; nothing outside host/scene includes it.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "scene/scene.hpp"

namespace oas::scene::detail {

using json = nlohmann::json;

// Pieces of messages.
std::string join(std::initializer_list<std::string_view> items, std::string_view sep = ", ");
std::string join(const std::vector<std::string>& items, std::string_view sep = ", ");
/// "path.key" ("key" at the root) and "path[index]": the JSON paths messages name.
std::string child(const std::string& path, std::string_view key);
std::string element(const std::string& path, std::size_t index);
/// A JSON value for a message: numbers as numbers, strings quoted, containers abbreviated.
std::string show(const json& v);
std::string show(const glm::vec3& v);
/// "integer", "number", "boolean", "string", "array", "object" or "null".
std::string typeName(const json& v);
/// Case-insensitive Levenshtein distance, for "did you mean" hints.
std::size_t editDistance(std::string_view a, std::string_view b);

/// The parsed file; duplicate keys, nesting deeper than 64 levels, NUL bytes and syntax errors
/// are SceneErrors naming the path they were found at.
json parseJson(const std::string& text, const std::string& file);

/// Typed access to the fields of one scene file: each reader returns the value or throws a
/// SceneError for `file` at the path it is given.
class FieldReader {
public:
    explicit FieldReader(std::string file) : file_(std::move(file)) {}

    [[noreturn]] void fail(const std::string& path, const std::string& detail) const;

    // Structure.
    static const json* find(const json& obj, const char* key);
    const json& require(const json& obj, const std::string& path, const char* key, std::string_view valid) const;
    /// The node must be an object whose keys are all in `allowed` ("comment" is always allowed).
    void objectKeys(const json& obj, const std::string& path, std::string_view what,
                    std::initializer_list<std::string_view> allowed) const;
    /// The node at `path` must be an array of objects ("an array of WHAT objects"); calls
    /// visit(object, "path[i]") for each element in order.
    template <class Visit>
    void forEachObject(const json& v, const std::string& path, std::string_view what, Visit&& visit) const
    {
        if (!v.is_array()) typeError(v, path, "an array", "an array of " + std::string(what) + " objects");
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string elementPath = element(path, i);
            if (!v[i].is_object()) typeError(v[i], elementPath, "an object", "a " + std::string(what) + " object");
            visit(v[i], elementPath);
        }
    }

    // Scalars.
    [[noreturn]] void typeError(const json& v, const std::string& path, std::string_view expected, std::string_view valid) const;
    /// A finite number that is also finite as a 32-bit float.
    float real(const json& v, const std::string& path, std::string_view valid = "any finite number") const;
    /// A number in [lo, hi] (open ends where loOpen / hiOpen); `valid` describes the range.
    float realIn(const json& v, const std::string& path, double lo, double hi, std::string_view valid, bool loOpen = false,
                 bool hiOpen = false) const;
    std::uint32_t integer(const json& v, const std::string& path, std::uint32_t lo, std::uint32_t hi,
                          std::string_view valid) const;
    bool boolean(const json& v, const std::string& path) const;
    std::string string(const json& v, const std::string& path, std::string_view valid = "a string") const;
    std::string choice(const json& v, const std::string& path, std::initializer_list<std::string_view> valid,
                       std::string_view extraHint = {}) const;

    // Vectors.
    glm::vec3 vec3(const json& v, const std::string& path) const;
    /// A colour: one number (grey) or [r, g, b], each component in [lo, hi].
    glm::vec3 color(const json& v, const std::string& path, float lo, float hi) const;
    /// v / |v| with the length taken in double: in float, |v| of a huge vector overflows and
    /// normalize() returns zeros (a spot direction of [3e38, 3e38, 3e38] became [0, 0, 0]).
    static glm::vec3 unitVector(const glm::vec3& v);
    glm::vec3 nonzeroVec3(const json& v, const std::string& path, std::string_view what) const;

private:
    std::string file_;
};

}  // namespace oas::scene::detail
