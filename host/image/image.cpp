// OpenEXR reading and writing (OpenEXR's C++ API) for oas::image::Image.
#include "image/image.hpp"
#include "oas/atomic_file.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

namespace oas::image {

Image::Image(std::uint32_t w, std::uint32_t h, float r, float g, float b, float a) : width(w), height(h)
{
    rgba.resize(std::size_t(w) * h * 4);
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
        rgba[i] = r;
        rgba[i + 1] = g;
        rgba[i + 2] = b;
        rgba[i + 3] = a;
    }
}

void checkLayout(const Image& image, const char* what)
{
    const std::size_t expected = std::size_t(image.width) * image.height * 4;
    if (image.rgba.size() != expected)
        throw std::invalid_argument(std::string(what) + " is " + std::to_string(image.width) + "x" +
                                    std::to_string(image.height) + " but holds " + std::to_string(image.rgba.size()) +
                                    " floats, not " + std::to_string(expected));
}

namespace {

/// An Imf::OStream over a stdio FILE that remembers any failure, so that errors OpenEXR swallows
/// (its OutputFile destructor writes the line-offset table and cannot throw) are still seen.
class FileOStream final : public Imf::OStream {
public:
    FileOStream(const std::string& name, std::FILE* file) : Imf::OStream(name.c_str()), file_(file) {}

    void write(const char c[], int n) override
    {
        if (n > 0 && std::fwrite(c, 1, std::size_t(n), file_) != std::size_t(n)) fail("write");
    }
    std::uint64_t tellp() override
    {
        const off_t pos = ::ftello(file_);
        if (pos < 0) fail("tell");
        return std::uint64_t(pos);
    }
    void seekp(std::uint64_t pos) override
    {
        if (::fseeko(file_, off_t(pos), SEEK_SET) != 0) fail("seek");
    }
    bool failed() const { return !error_.empty(); }
    const std::string& error() const { return error_; }

private:
    [[noreturn]] void fail(const char* what)
    {
        if (error_.empty()) error_ = std::string(what) + ": " + std::strerror(errno);
        throw std::runtime_error(error_);
    }
    std::FILE* file_;
    std::string error_;
};

/// Header attributes that describe the file's structure; a user string attribute may not use them.
bool isReservedAttribute(const Imf::Header& header, const std::string& name)
{
    static const char* const kStructural[] = {"tiles", "type",     "name", "version", "chunkCount", "maxSamplesPerPixel",
                                              "view",  "multiView"};
    if (header.find(name) != header.end()) return true;
    for (const char* s : kStructural)
        if (name == s) return true;
    return false;
}

}  // namespace

void writeExr(const std::string& path, const Image& image, const std::map<std::string, std::string>& headerAttributes,
              const UintChannels& uintChannels)
{
    checkLayout(image);
    if (image.width == 0 || image.height == 0 || image.width > INT_MAX || image.height > INT_MAX)
        throw std::invalid_argument("cannot write '" + path + "': an EXR image must be 1x1 .. 2^31-1 square, not " +
                                    std::to_string(image.width) + "x" + std::to_string(image.height));
    const int w = int(image.width), h = int(image.height);

    Imf::Header header(w, h);
    header.compression() = Imf::ZIP_COMPRESSION;  // lossless
    for (const char* c : {"R", "G", "B", "A"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const auto& [name, values] : uintChannels) {
        if (name.empty() || header.channels().findChannel(name))
            throw std::invalid_argument("cannot write '" + path + "': uint channel name '" + name +
                                        "' is empty or taken by R, G, B, A");
        if (values.size() != image.pixelCount())
            throw std::invalid_argument("cannot write '" + path + "': uint channel '" + name + "' holds " +
                                        std::to_string(values.size()) + " values for " + std::to_string(image.pixelCount()) +
                                        " pixels");
        header.channels().insert(name, Imf::Channel(Imf::UINT));
    }
    for (const auto& [name, value] : headerAttributes) {
        if (name.empty()) throw std::invalid_argument("cannot write '" + path + "': empty EXR attribute name");
        if (isReservedAttribute(header, name))
            throw std::invalid_argument("cannot write '" + path + "': EXR attribute name '" + name + "' is reserved by OpenEXR");
        header.insert(name, Imf::StringAttribute(value));
    }

    Imf::FrameBuffer frameBuffer;
    const std::size_t xStride = 4 * sizeof(float), yStride = xStride * image.width;
    const char* names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
        frameBuffer.insert(names[c], Imf::Slice::Make(Imf::FLOAT, image.rgba.data() + c, header.dataWindow(), xStride, yStride));
    for (const auto& [name, values] : uintChannels)
        frameBuffer.insert(name, Imf::Slice::Make(Imf::UINT, values.data(), header.dataWindow(), sizeof(std::uint32_t),
                                                  sizeof(std::uint32_t) * image.width));

    oas::removeStaleTemporaries(path);
    const std::string tmp = oas::temporaryPathFor(path);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) throw std::runtime_error("cannot write '" + path + "' (open '" + tmp + "'): " + std::strerror(errno));
    std::FILE* file = ::fdopen(fd, "wb");
    if (!file) {
        const std::string reason = std::strerror(errno);
        ::close(fd);
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path + "' (fdopen): " + reason);
    }

    std::string error;
    {
        FileOStream stream(tmp, file);
        try {
            Imf::OutputFile out(stream, header);
            out.setFrameBuffer(frameBuffer);
            out.writePixels(h);
        } catch (const std::exception& e) {
            error = e.what();
        }
        // ~OutputFile has written the line-offset table by now; it swallows failures, the stream does not.
        if (error.empty() && stream.failed()) error = stream.error();
    }
    if (std::fflush(file) != 0 && error.empty()) error = std::string("write: ") + std::strerror(errno);
    if (std::fclose(file) != 0 && error.empty()) error = std::string("close: ") + std::strerror(errno);
    if (error.empty() && std::rename(tmp.c_str(), path.c_str()) != 0) error = std::string("rename: ") + std::strerror(errno);
    if (!error.empty()) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path + "': " + error);
    }
}

Image readExr(const std::string& path, std::map<std::string, std::string>* attributes, UintChannels* uintChannels)
{
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i dataWindow = header.dataWindow();
        const std::int64_t w = std::int64_t(dataWindow.max.x) - dataWindow.min.x + 1;
        const std::int64_t h = std::int64_t(dataWindow.max.y) - dataWindow.min.y + 1;
        if (w <= 0 || h <= 0 || w > UINT32_MAX || h > UINT32_MAX) throw std::runtime_error("empty data window");

        std::string missing, present;
        for (const char* c : {"R", "G", "B"})
            if (!header.channels().findChannel(c)) missing += missing.empty() ? c : std::string(", ") + c;
        if (!missing.empty()) {
            for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
                present += (present.empty() ? "" : ", ") + std::string(it.name());
            throw std::runtime_error("no " + missing + " channel (it has: " + (present.empty() ? "none" : present) + ")");
        }

        Image image;
        image.width = std::uint32_t(w);
        image.height = std::uint32_t(h);
        image.rgba.resize(std::size_t(w) * std::size_t(h) * 4);
        Imf::FrameBuffer frameBuffer;
        const std::size_t xStride = 4 * sizeof(float), yStride = xStride * std::size_t(w);
        const char* names[4] = {"R", "G", "B", "A"};
        for (int c = 0; c < 4; ++c)
            frameBuffer.insert(names[c], Imf::Slice::Make(Imf::FLOAT, image.rgba.data() + c, dataWindow, xStride, yStride, 1, 1,
                                                          c == 3 ? 1.0 : 0.0));
        if (uintChannels) {
            uintChannels->clear();
            for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
                if (it.channel().type != Imf::UINT) continue;
                if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
                    throw std::runtime_error(std::string("uint channel '") + it.name() + "' is subsampled");
                std::vector<std::uint32_t>& values = (*uintChannels)[it.name()];
                values.assign(std::size_t(w) * std::size_t(h), 0u);
                frameBuffer.insert(it.name(), Imf::Slice::Make(Imf::UINT, values.data(), dataWindow, sizeof(std::uint32_t),
                                                               sizeof(std::uint32_t) * std::size_t(w)));
            }
        }
        file.setFrameBuffer(frameBuffer);
        file.readPixels(dataWindow.min.y, dataWindow.max.y);

        if (attributes) {
            attributes->clear();
            for (auto it = header.begin(); it != header.end(); ++it)
                if (std::strcmp(it.attribute().typeName(), Imf::StringAttribute::staticTypeName()) == 0)
                    (*attributes)[it.name()] = static_cast<const Imf::StringAttribute&>(it.attribute()).value();
        }
        return image;
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot read EXR '" + path + "': " + e.what());
    }
}

}  // namespace oas::image
