#include "oas/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <unistd.h>

namespace oas {

void writeFileAtomically(const std::string& path, std::string_view bytes)
{
    const std::string tmp = path + ".tmp." + std::to_string(::getpid());
    auto fail = [&](const char* what) {
        const std::string reason = std::strerror(errno);
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path + "' (" + what + "): " + reason);
    };
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) fail("open");
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed) fail("write");
    if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("rename");
}

}  // namespace oas
