#pragma once
// A small Wavefront OBJ reader for triangle meshes: `v` and `f` statements only.
//   v x y z [w]            (w, and the r g b of the common "v x y z r g b" extension, are ignored)
//   f a b c ...            each corner v, v/vt, v//vn or v/vt/vn; indices are 1-based, negative
//                          indices count back from the last element defined so far (-1 = last)
// Polygons are fan-triangulated (a b c d -> abc, acd). vt/vn indices are checked against the
// `vt`/`vn` statements but not kept. Every other statement (o, g, s, usemtl, mtllib, vp, l, p...)
// and `#` comments are ignored; a trailing backslash continues a line. Zero-area triangles are
// dropped and counted. Errors throw ObjError naming "file:line".
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace oas::scene {

class ObjError : public std::runtime_error {
public:
    /// line 0: the problem is with the whole file (missing, unreadable).
    ObjError(std::string file, std::size_t line, const std::string& detail);
    const std::string& file() const { return file_; }
    std::size_t line() const { return line_; }

private:
    std::string file_;
    std::size_t line_;
};

struct ObjMesh {
    std::vector<glm::vec3> positions;                     ///< every `v`, in file order
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< 0-based indices into positions
    std::size_t faces = 0;                                ///< `f` statements read
    std::size_t degenerateDropped = 0;                    ///< zero-area triangles left out of `triangles`
};

/// Thinness (twice the area over the longest edge squared) at or below which a triangle or a
/// parallelogram counts as zero-area: well above what float32 rounding leaves of exactly collinear
/// or parallel decimal input (~1e-7), so such input is refused rather than traced as a sliver.
constexpr double kMinThinness = 1e-5;

/// True when the triangle has zero area to within rounding: |cross(b - a, c - a)| is at most
/// kMinThinness times the longest edge squared (computed in double), or all points coincide.
bool isDegenerateTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);
/// The same test for the parallelogram spanned by two edges, computed from the edges (not from
/// corner + edge sums, which float32 rounds so that parallel edges look slightly apart).
bool isDegenerateParallelogram(const glm::vec3& edgeU, const glm::vec3& edgeV);

/// Parses OBJ text; nameForMessages is the file name used in errors.
ObjMesh parseObj(std::string_view text, const std::string& nameForMessages);
/// Reads an OBJ file (errors name it as given).
ObjMesh readObj(const std::filesystem::path& file);

}  // namespace oas::scene
