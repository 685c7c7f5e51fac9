// Wavefront OBJ reader: see obj.hpp for what is read and what is ignored.
#include "scene/obj.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

namespace oas::scene {

ObjError::ObjError(std::string file, std::size_t line, const std::string& detail)
    : std::runtime_error(line ? fmt::format("{}:{}: {}", file, line, detail) : fmt::format("{}: {}", file, detail)),
      file_(std::move(file)), line_(line)
{
}

bool isDegenerateTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c)
{
    // In double, so the test itself adds no rounding. Thinness = twice the area over the longest
    // edge squared (height / length). Points that are collinear as decimals are only nearly so once
    // rounded to float32 (thinness ~1e-7); 1e-5 refuses those and anything thinner, which float32
    // tracing could not resolve anyway.
    const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    const double e3[3] = {double(c.x) - b.x, double(c.y) - b.y, double(c.z) - b.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const auto len2 = [](const double* v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; };
    const double longest2 = std::max({len2(e1), len2(e2), len2(e3)});
    const double twiceArea = std::sqrt(len2(n));
    return !(longest2 > 0) || !(twiceArea > kMinThinness * longest2);
}

bool isDegenerateParallelogram(const glm::vec3& edgeU, const glm::vec3& edgeV)
{
    // From the edges themselves: corner + edge sums in float32 would round parallel edges apart.
    return isDegenerateTriangle(glm::vec3(0.0f), edgeU, edgeV);
}

namespace {

bool isSpace(char c)
{
    return c == ' ' || c == '\t' || c == '\v' || c == '\f';
}

std::vector<std::string_view> tokens(std::string_view line)
{
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isSpace(line[i])) ++i;
        const std::size_t start = i;
        while (i < line.size() && !isSpace(line[i])) ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

class Parser {
public:
    Parser(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {}

    ObjMesh run()
    {
        std::string logical;
        std::size_t pos = 0, lineNo = 0;
        while (pos < text_.size()) {
            // One logical line: physical lines joined where one ends in a backslash.
            logical.clear();
            const std::size_t startLine = lineNo + 1;
            for (;;) {
                std::size_t end = text_.find('\n', pos);
                if (end == std::string_view::npos) end = text_.size();
                std::string_view physical = text_.substr(pos, end - pos);
                pos = end + 1;
                ++lineNo;
                if (!physical.empty() && physical.back() == '\r') physical.remove_suffix(1);
                if (!physical.empty() && physical.back() == '\\' && pos < text_.size()) {
                    physical.remove_suffix(1);
                    logical.append(physical);
                    logical.push_back(' ');
                    continue;
                }
                logical.append(physical);
                break;
            }
            line_ = startLine;
            statement(logical);
        }
        return std::move(mesh_);
    }

private:
    [[noreturn]] void fail(const std::string& detail) const { throw ObjError(name_, line_, detail); }

    void statement(std::string_view line)
    {
        if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        const auto tok = tokens(line);
        if (tok.empty()) return;
        if (tok[0] == "v")
            vertex(tok);
        else if (tok[0] == "vt")
            ++texcoords_;
        else if (tok[0] == "vn")
            ++normals_;
        else if (tok[0] == "f")
            face(tok);
        // Anything else (o, g, s, usemtl, mtllib, vp, l, p, curves...) is ignored.
    }

    float number(std::string_view tok, const char* what)
    {
        std::string_view digits = tok;
        if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
        float value = 0;
        const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (ec == std::errc::result_out_of_range)
            fail(fmt::format("{} '{}' is out of range: valid finite 32-bit floats (|x| < 3.4e38)", what, tok));
        if (ec != std::errc() || ptr != digits.data() + digits.size() || digits.empty())
            fail(fmt::format("{} '{}' is not a number", what, tok));
        if (!std::isfinite(value)) fail(fmt::format("{} '{}' is not finite: valid finite numbers", what, tok));
        return value;
    }

    void vertex(const std::vector<std::string_view>& tok)
    {
        if (tok.size() < 4 || tok.size() > 8)
            fail(fmt::format("'v' needs x y z (optionally w, or r g b), got {} numbers", tok.size() - 1));
        static const char* names[] = {"x", "y", "z", "w", "value", "value", "value"};
        float xyz[3] = {};
        for (std::size_t i = 1; i < tok.size(); ++i) {
            const float v = number(tok[i], (std::string("vertex ") + names[i - 1]).c_str());
            if (i <= 3) xyz[i - 1] = v;
        }
        mesh_.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
    }

    /// A 1-based or negative OBJ index into `count` elements defined so far -> 0-based.
    std::uint32_t resolve(std::string_view tok, std::string_view corner, const char* kind, const char* plural, std::size_t count)
    {
        long long v = 0;
        const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (tok.empty() || ec != std::errc() || ptr != tok.data() + tok.size())
            fail(fmt::format("face corner '{}': {} index '{}' is not an integer", corner, kind, tok));
        const long long n = static_cast<long long>(count);
        if (v == 0 || v > n || v < -n) {
            if (n == 0)
                fail(fmt::format("face corner '{}': {} index {} is out of range: no {} defined before this line", corner, kind, v,
                                 plural));
            fail(fmt::format("face corner '{}': {} index {} is out of range: {} {} defined so far, valid 1..{} or -{}..-1",
                             corner, kind, v, n, plural, n, n));
        }
        return static_cast<std::uint32_t>(v > 0 ? v - 1 : n + v);
    }

    void face(const std::vector<std::string_view>& tok)
    {
        if (tok.size() < 4) fail(fmt::format("'f' needs at least 3 vertices, got {}", tok.size() - 1));
        ++mesh_.faces;
        std::vector<std::uint32_t> idx;
        idx.reserve(tok.size() - 1);
        for (std::size_t i = 1; i < tok.size(); ++i) {
            const std::string_view corner = tok[i];
            // v | v/vt | v//vn | v/vt/vn
            const std::size_t s1 = corner.find('/');
            const std::string_view vPart = corner.substr(0, s1);
            idx.push_back(resolve(vPart, corner, "vertex", "vertices", mesh_.positions.size()));
            if (s1 == std::string_view::npos) continue;
            const std::string_view rest = corner.substr(s1 + 1);
            const std::size_t s2 = rest.find('/');
            const std::string_view vtPart = rest.substr(0, s2);
            if (s2 == std::string_view::npos) {  // v/vt
                resolve(vtPart, corner, "texture coordinate", "texture coordinates", texcoords_);
                continue;
            }
            const std::string_view vnPart = rest.substr(s2 + 1);
            if (vnPart.find('/') != std::string_view::npos)
                fail(fmt::format("face corner '{}' is malformed: valid forms v, v/vt, v//vn, v/vt/vn", corner));
            if (!vtPart.empty()) resolve(vtPart, corner, "texture coordinate", "texture coordinates", texcoords_);
            resolve(vnPart, corner, "normal", "normals", normals_);
        }
        const auto& p = mesh_.positions;
        for (std::size_t i = 1; i + 1 < idx.size(); ++i) {
            const std::array<std::uint32_t, 3> tri{idx[0], idx[i], idx[i + 1]};
            if (isDegenerateTriangle(p[tri[0]], p[tri[1]], p[tri[2]]))
                ++mesh_.degenerateDropped;
            else
                mesh_.triangles.push_back(tri);
        }
    }

    std::string_view text_;
    std::string name_;
    std::size_t line_ = 0;
    std::size_t texcoords_ = 0, normals_ = 0;
    ObjMesh mesh_;
};

}  // namespace

ObjMesh parseObj(std::string_view text, const std::string& nameForMessages)
{
    return Parser(text, nameForMessages).run();
}

ObjMesh readObj(const std::filesystem::path& file)
{
    std::error_code ec;
    const auto status = std::filesystem::status(file, ec);
    if (!std::filesystem::exists(status)) throw ObjError(file.string(), 0, "mesh file not found (no such file)");
    if (std::filesystem::is_directory(status)) throw ObjError(file.string(), 0, "is a directory, not a mesh file");
    // A device or FIFO ("/dev/zero", a pipe) would be read without end or block forever.
    if (!std::filesystem::is_regular_file(status))
        throw ObjError(file.string(), 0, "is not a regular file (a device, FIFO or socket): valid an OBJ file");
    constexpr std::uintmax_t kMaxObjBytes = std::uintmax_t(1) << 30;
    if (const auto size = std::filesystem::file_size(file, ec); !ec && size > kMaxObjBytes)
        throw ObjError(file.string(), 0, "is " + std::to_string(size) + " bytes: valid OBJ files up to 1 GiB");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ObjError(file.string(), 0, "cannot open the mesh file for reading");
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw ObjError(file.string(), 0, "error reading the mesh file");
    return parseObj(buffer.str(), file.string());
}

}  // namespace oas::scene
