#pragma once
// Output files appear whole or not at all: write to "<path>.tmp.<pid>", then rename over path.
#include <string>
#include <string_view>

namespace oas {
/// Writes `bytes` to `path` atomically; throws std::runtime_error naming the path on failure
/// (the temporary file is removed).
void writeFileAtomically(const std::string& path, std::string_view bytes);
}  // namespace oas
