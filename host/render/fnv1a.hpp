#pragma once
// FNV-1a, 64 bits (Fowler, Noll and Vo): a short, exact fingerprint of bytes. Render files hash
// the flattened scene with it (oas.sceneHash); the tracer's refactor guard hashes a render's sums.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace oas::render {

/// FNV-1a over the bytes given, in order (the flattened scene's structs are built from vec4s with
/// no padding, so their bytes are their values).
struct Fnv1a {
    std::uint64_t h = 0xcbf29ce484222325ull;
    void bytes(const void* data, std::size_t size)
    {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    }
    template <class T>
    void items(const std::vector<T>& v)
    {
        const std::uint64_t n = v.size();
        bytes(&n, sizeof n);
        bytes(v.data(), v.size() * sizeof(T));
    }
};

}  // namespace oas::render
