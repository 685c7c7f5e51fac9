#include "oas/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace oas {

std::string temporaryPathFor(const std::string& path)
{
    static std::atomic<unsigned> counter{0};
    return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter.fetch_add(1));
}

std::size_t removeStaleTemporaries(const std::string& path)
{
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    const std::string prefix = target.filename().string() + ".tmp.";
    if (prefix == ".tmp.") return 0;
    std::size_t removed = 0;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
        // The rest must be <pid> or <pid>.<n>, decimal: anything else is not ours.
        const std::string rest = name.substr(prefix.size());
        const std::size_t dot = rest.find('.');
        const auto digits = [](const std::string& s) {
            return !s.empty() && s.size() <= 10 && s.find_first_not_of("0123456789") == std::string::npos;
        };
        const std::string pidText = rest.substr(0, dot);
        if (!digits(pidText) || (dot != std::string::npos && !digits(rest.substr(dot + 1)))) continue;
        const long long pid = std::stoll(pidText);
        if (pid <= 0 || pid > 0x7fffffff || pid == ::getpid()) continue;
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
        std::error_code removeError;
        if (fs::remove(it->path(), removeError)) ++removed;
    }
    return removed;
}

void writeFileAtomically(const std::string& path, std::string_view bytes)
{
    removeStaleTemporaries(path);
    const std::string tmp = temporaryPathFor(path);
    auto fail = [&](const char* what) {
        const std::string reason = std::strerror(errno);
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path + "' (" + what + "): " + reason);
    };
    std::FILE* f = std::fopen(tmp.c_str(), "wbx");
    if (!f) fail("open");
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed) fail("write");
    if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("rename");
}

}  // namespace oas
