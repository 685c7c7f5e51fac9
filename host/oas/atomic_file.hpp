#pragma once
// Output files appear whole or not at all: write to "<path>.tmp.<pid>.<n>", then rename over path.
// A process killed mid-write (SIGKILL, power loss) leaves its temporary file behind; the next write
// of the same path removes such files of processes that no longer exist.
#include <string>
#include <string_view>

namespace oas {
/// Writes `bytes` to `path` atomically; throws std::runtime_error naming the path on failure
/// (the temporary file is removed).
void writeFileAtomically(const std::string& path, std::string_view bytes);

/// A fresh temporary name beside `path` in our own pattern, "<path>.tmp.<pid>.<n>", for writers
/// that stream (OpenEXR) and rename themselves.
std::string temporaryPathFor(const std::string& path);

/// Removes the temporary files of `path` ("<path>.tmp.<pid>" or "<path>.tmp.<pid>.<n>") whose
/// process no longer exists. Files of live processes, and every other file, are left alone.
/// Returns how many were removed; never throws (a directory that cannot be listed is skipped).
std::size_t removeStaleTemporaries(const std::string& path);
}  // namespace oas
