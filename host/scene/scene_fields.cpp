// The JSON-field readers and message pieces every section of the scene loader shares
// (scene_fields.hpp).
#include "scene/scene_fields.hpp"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

namespace oas::scene::detail {

std::string join(std::initializer_list<std::string_view> items, std::string_view sep)
{
    std::string out;
    for (auto item : items) {
        if (!out.empty()) out += sep;
        out += item;
    }
    return out;
}

std::string join(const std::vector<std::string>& items, std::string_view sep)
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

std::string element(const std::string& path, std::size_t index)
{
    return fmt::format("{}[{}]", path, index);
}

/// Appends a compact rendering of v to out, stopping once out holds more than `limit` characters,
/// so that a message about a huge or deeply nested value costs O(limit), not O(size) (json::dump
/// recursed through every level and crashed on deep input; parseJson also caps the depth).
namespace {

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

}  // namespace

std::string show(const json& v)
{
    if (v.is_number_float()) return fmt::format("{}", v.get<double>());
    constexpr std::size_t kShown = 60;
    std::string text;
    abbreviate(v, text, kShown);
    if (text.size() > kShown) text = text.substr(0, kShown - 3) + "...";
    return text;
}

std::string show(const glm::vec3& v)
{
    return fmt::format("[{}, {}, {}]", v.x, v.y, v.z);
}

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
            const bool same =
                std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (same ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

void FieldReader::fail(const std::string& path, const std::string& detail) const
{
    throw SceneError(file_, path, detail);
}

// --- structure -----------------------------------------------------------------------------

const json* FieldReader::find(const json& obj, const char* key)
{
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
}

const json& FieldReader::require(const json& obj, const std::string& path, const char* key, std::string_view valid) const
{
    if (auto* v = find(obj, key)) return *v;
    fail(child(path, key), fmt::format("missing (required): valid {}", valid));
}

void FieldReader::objectKeys(const json& obj, const std::string& path, std::string_view what,
                             std::initializer_list<std::string_view> allowed) const
{
    if (!obj.is_object())
        typeError(obj, path.empty() ? "(root)" : path, fmt::format("an object for {}", what), "an object (see scenes/README.md)");
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
        fail(child(path, key),
             fmt::format("unknown key \"{}\" in {}{}: valid keys are {}, comment", key, what, hint, join(allowed)));
    }
}

// --- scalars -------------------------------------------------------------------------------

void FieldReader::typeError(const json& v, const std::string& path, std::string_view expected, std::string_view valid) const
{
    fail(path, fmt::format("expected {}, got {} {}: valid {}", expected, typeName(v), show(v), valid));
}

float FieldReader::real(const json& v, const std::string& path, std::string_view valid) const
{
    if (!v.is_number()) typeError(v, path, "a number", valid);
    const double d = v.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > double(FLT_MAX))
        fail(path, fmt::format("{} is not a finite 32-bit float: valid |x| < 3.4e38", show(v)));
    return float(d);
}

float FieldReader::realIn(const json& v, const std::string& path, double lo, double hi, std::string_view valid, bool loOpen,
                          bool hiOpen) const
{
    const float f = real(v, path, valid);
    const bool ok = (loOpen ? f > lo : f >= lo) && (hiOpen ? f < hi : f <= hi);
    if (!ok) fail(path, fmt::format("{} is out of range: valid {}", show(v), valid));
    return f;
}

std::uint32_t FieldReader::integer(const json& v, const std::string& path, std::uint32_t lo, std::uint32_t hi,
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

bool FieldReader::boolean(const json& v, const std::string& path) const
{
    if (!v.is_boolean()) typeError(v, path, "a boolean", "true | false");
    return v.get<bool>();
}

std::string FieldReader::string(const json& v, const std::string& path, std::string_view valid) const
{
    if (!v.is_string()) typeError(v, path, "a string", valid);
    return v.get<std::string>();
}

std::string FieldReader::choice(const json& v, const std::string& path, std::initializer_list<std::string_view> valid,
                                std::string_view extraHint) const
{
    const std::string s = string(v, path, join(valid, " | "));
    if (std::find(valid.begin(), valid.end(), s) == valid.end())
        fail(path, fmt::format("\"{}\" is not valid: valid {}{}", s, join(valid, " | "), extraHint));
    return s;
}

// --- vectors -------------------------------------------------------------------------------

glm::vec3 FieldReader::vec3(const json& v, const std::string& path) const
{
    if (!v.is_array() || v.size() != 3) typeError(v, path, "[x, y, z]", "3 finite numbers");
    return {real(v[0], element(path, 0)), real(v[1], element(path, 1)), real(v[2], element(path, 2))};
}

glm::vec3 FieldReader::color(const json& v, const std::string& path, float lo, float hi) const
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
    if (!v.is_array() || v.size() != 3) typeError(v, path, "a colour", fmt::format("one number or [r, g, b], each {}", valid));
    return {component(v[0], element(path, 0)), component(v[1], element(path, 1)), component(v[2], element(path, 2))};
}

/// v / |v| with the length taken in double: in float, |v| of a huge vector overflows and
/// normalize() returns zeros (a spot direction of [3e38, 3e38, 3e38] became [0, 0, 0]).
glm::vec3 FieldReader::unitVector(const glm::vec3& v)
{
    const double len = std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z);
    return glm::vec3(float(v.x / len), float(v.y / len), float(v.z / len));
}

glm::vec3 FieldReader::nonzeroVec3(const json& v, const std::string& path, std::string_view what) const
{
    const glm::vec3 r = vec3(v, path);
    if (!(glm::length(r) > 0)) fail(path, fmt::format("{} {} has zero length: valid nonzero {}", what, show(r), what));
    return r;
}

}  // namespace oas::scene::detail
