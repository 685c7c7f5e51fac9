// The image layer: float32 OpenEXR round trips (bits, attributes, atomic failure), sRGB PNG
// previews checked against the sRGB formula computed here, error metrics against hand-computed
// answers, the false-colour error ramp, and oas-diff run as a child process (path from the
// OAS_DIFF_EXE compile definition).
#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <csignal>
#include <cstdio>

#include <fcntl.h>
#include <sys/resource.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "image/image.hpp"
#include "image/metrics.hpp"
#include "oas/atomic_file.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#if __has_include(<stb_image.h>)
#include <stb_image.h>
#else
#include <stb/stb_image.h>
#endif
#pragma GCC diagnostic pop

#ifndef OAS_DIFF_EXE
#error "define OAS_DIFF_EXE as the path of the oas-diff binary"
#endif

extern char** environ;

namespace {

namespace fs = std::filesystem;
using oas::image::Crop;
using oas::image::Image;

/// A fresh empty directory, removed with its contents at the end of the test.
struct TempDir {
    fs::path path;
    TempDir()
    {
        static int counter = 0;
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path = fs::temp_directory_path() /
               ("oas_image_test." + std::to_string(::getpid()) + "." + std::to_string(counter++) + "." + info->name());
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir()
    {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string operator/(const std::string& name) const { return (path / name).string(); }
    std::vector<std::string> entries() const
    {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(path)) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
};

std::string readBytes(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::uint32_t bitsOf(float f)
{
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}

float floatOf(std::uint32_t u)
{
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

// ---------------------------------------------------------------------------------------------
// OpenEXR

TEST(Exr, RoundTripIsBitExactForAllFloats)
{
    TempDir dir;
    Image image(7, 5);
    const float specials[] = {0.0f,
                              -0.0f,
                              std::numeric_limits<float>::denorm_min(),
                              -std::numeric_limits<float>::denorm_min(),
                              std::numeric_limits<float>::min(),
                              std::numeric_limits<float>::max(),
                              -std::numeric_limits<float>::max(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::quiet_NaN(),
                              floatOf(0x7fc12345u),  // NaN with a payload
                              1e-30f,
                              1e30f,
                              3.0e38f,
                              1.17549e-38f,
                              0.1f,
                              65504.0f,
                              65520.0f,  // beyond half's range
                              1.0f + 1.1920929e-7f,
                              -123456.789f};
    std::mt19937 rng(12345);
    for (std::size_t i = 0; i < image.rgba.size(); ++i)
        image.rgba[i] = i < std::size(specials) ? specials[i] : floatOf(std::uint32_t(rng()));
    const std::map<std::string, std::string> attributes = {
        {"oas.spp", "64"},
        {"oas.sampler", "bush-oa t=2 (cmj offsets)"},
        {"oas.renderTimeSeconds", "12.345678901"},
        {"oas.dimensionPlan", "{\"camera\": [0, 1], \"lens\": [2, 3],\n \"light\": [4, 5]} \xc2\xb5"},
        {"oas.empty", ""}};
    const std::string path = dir / "round.exr";
    oas::image::writeExr(path, image, attributes);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"round.exr"});  // no temporary left behind

    std::map<std::string, std::string> readAttributes;
    const Image back = oas::image::readExr(path, &readAttributes);
    ASSERT_EQ(back.width, 7u);
    ASSERT_EQ(back.height, 5u);
    ASSERT_EQ(back.rgba.size(), image.rgba.size());
    for (std::size_t i = 0; i < image.rgba.size(); ++i)
        ASSERT_EQ(bitsOf(back.rgba[i]), bitsOf(image.rgba[i])) << "value " << i << " = " << image.rgba[i];
    for (const auto& [name, value] : attributes) {
        ASSERT_TRUE(readAttributes.count(name)) << name;
        EXPECT_EQ(readAttributes.at(name), value) << name;
    }

    // The file really is float32 RGBA (not half), with lossless compression.
    Imf::InputFile file(path.c_str());
    const Imf::ChannelList& channels = file.header().channels();
    int count = 0;
    for (auto it = channels.begin(); it != channels.end(); ++it, ++count) EXPECT_EQ(it.channel().type, Imf::FLOAT) << it.name();
    EXPECT_EQ(count, 4);
    for (const char* c : {"R", "G", "B", "A"}) EXPECT_NE(channels.findChannel(c), nullptr) << c;
}

TEST(Exr, OverwritesAnExistingFile)
{
    TempDir dir;
    const std::string path = dir / "x.exr";
    oas::image::writeExr(path, Image(2, 2, 1, 2, 3), {{"oas.spp", "1"}});
    oas::image::writeExr(path, Image(3, 1, 4, 5, 6), {{"oas.spp", "2"}});
    std::map<std::string, std::string> attributes;
    const Image back = oas::image::readExr(path, &attributes);
    EXPECT_EQ(back.width, 3u);
    EXPECT_EQ(back.rgba[0], 4.0f);
    EXPECT_EQ(attributes.at("oas.spp"), "2");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"x.exr"});
}

TEST(Exr, ReadsHalfRgbWithoutAlphaAndOffsetDataWindow)
{
    TempDir dir;
    const std::string path = dir / "half.exr";
    const Imath::Box2i display({0, 0}, {9, 9}), data({3, 2}, {6, 4});  // 4 x 3 pixels at (3, 2)
    Imf::Header header(display, data);
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::HALF));
    std::vector<half> pixels(4 * 3 * 3);
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = half(0.25f * float(i) - 1.0f);
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
        fb.insert(names[c], Imf::Slice::Make(Imf::HALF, pixels.data() + c, data, 3 * sizeof(half), 12 * sizeof(half)));
    {
        Imf::OutputFile out(path.c_str(), header);
        out.setFrameBuffer(fb);
        out.writePixels(3);
    }
    const Image image = oas::image::readExr(path);
    ASSERT_EQ(image.width, 4u);
    ASSERT_EQ(image.height, 3u);
    for (std::size_t p = 0; p < 12; ++p) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(image.rgba[p * 4 + c], float(pixels[p * 3 + c])) << p << "," << c;
        EXPECT_EQ(image.rgba[p * 4 + 3], 1.0f) << "missing alpha reads as 1";
    }
}

TEST(Exr, ReadErrorsNameTheFile)
{
    TempDir dir;
    const std::string missing = dir / "missing.exr";
    try {
        oas::image::readExr(missing);
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }

    const std::string junk = dir / "junk.exr";
    std::ofstream(junk) << "this is not an OpenEXR file";
    try {
        oas::image::readExr(junk);
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(junk), std::string::npos) << e.what();
    }

    // A luminance-only file: no R, G, B.
    const std::string lum = dir / "y.exr";
    {
        Imf::Header header(2, 2);
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        std::vector<float> y(4, 0.5f);
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, y.data(), header.dataWindow()));
        Imf::OutputFile out(lum.c_str(), header);
        out.setFrameBuffer(fb);
        out.writePixels(2);
    }
    try {
        oas::image::readExr(lum);
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(lum), std::string::npos) << what;
        EXPECT_NE(what.find("R, G, B"), std::string::npos) << what;
        EXPECT_NE(what.find("Y"), std::string::npos) << what;
    }
}

/// The pid of a process that has exited (and been reaped): no process has it for a while.
pid_t deadPid()
{
    const pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return pid;
}

TEST(AtomicFile, StaleTemporariesOfDeadProcessesAreRemoved)
{
    // Regression (issue 8): a kill during a write left "x.exr.tmp.<pid>.0" / "x.png.tmp.<pid>"
    // behind for good. The next write of the same path removes those of processes that are gone;
    // a live process's file (it may be writing right now) and files not of our naming stay.
    TempDir dir;
    const std::string dead = std::to_string(deadPid()), live = std::to_string(::getppid());
    const std::vector<std::string> stale = {"x.exr.tmp." + dead + ".0", "x.exr.tmp." + dead + ".17", "x.png.tmp." + dead};
    const std::vector<std::string> kept = {"x.exr.tmp." + live + ".0", "x.exr.tmp.abc",      "x.exr.tmp." + dead + ".x",
                                           "y.exr.tmp." + dead + ".0", "x.exr.tmpl." + dead, "notes.txt"};
    for (const auto& name : stale) std::ofstream(dir / name) << "partial";
    for (const auto& name : kept) std::ofstream(dir / name) << "keep";
    oas::image::writeExr(dir / "x.exr", Image(2, 2, 0.5f, 0.5f, 0.5f), {});
    oas::image::writePngPreview(dir / "x.png", Image(2, 2, 0.5f, 0.5f, 0.5f));
    std::vector<std::string> expected = kept;
    expected.insert(expected.end(), {"x.exr", "x.png"});
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(dir.entries(), expected);
    EXPECT_EQ(oas::removeStaleTemporaries(dir / "y.exr"), 1u);
    EXPECT_EQ(oas::removeStaleTemporaries(dir / "y.exr"), 0u);
    EXPECT_EQ(oas::removeStaleTemporaries(dir / "missing-dir/z.exr"), 0u);
}

TEST(Exr, FailedWriteLeavesNothingAndNamesThePath)
{
    TempDir dir;
    const Image image(3, 2, 0.5f, 0.5f, 0.5f);

    // The directory does not exist: nothing can be created.
    const std::string noDir = dir / "no/such/dir/out.exr";
    try {
        oas::image::writeExr(noDir, image, {{"oas.spp", "4"}});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(noDir), std::string::npos) << e.what();
    }
    EXPECT_TRUE(dir.entries().empty());

    // The target is a directory: the whole file is written to the temporary, then the rename fails;
    // the temporary must be gone and the directory untouched.
    const std::string isDir = dir / "target.exr";
    fs::create_directory(isDir);
    try {
        oas::image::writeExr(isDir, image, {});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(isDir), std::string::npos) << e.what();
    }
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"target.exr"});
    EXPECT_TRUE(fs::is_directory(isDir));

    // A read-only directory (meaningless for root, who may write anyway).
    if (::geteuid() != 0) {
        const fs::path ro = dir.path / "readonly";
        fs::create_directory(ro);
        fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
        const std::string roPath = (ro / "out.exr").string();
        EXPECT_THROW(oas::image::writeExr(roPath, image, {}), std::runtime_error);
        fs::permissions(ro, fs::perms::owner_all);
        EXPECT_TRUE(fs::is_empty(ro));
    }
}

TEST(Exr, DiskFullLeavesNothing)
{
    // A child process with a 16 KiB file-size limit (SIGXFSZ ignored, so writes fail with EFBIG)
    // writes an incompressible 64x64 image: the write must throw naming the path, and leave no file.
    TempDir dir;
    const std::string path = dir / "full.exr";
    Image noise(64, 64);
    std::mt19937 rng(7);
    for (float& v : noise.rgba) v = floatOf(std::uint32_t(rng()) & 0x3fffffffu);
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    auto writeWithLimit = [&] {
        std::signal(SIGXFSZ, SIG_IGN);
        rlimit limit;
        limit.rlim_cur = limit.rlim_max = 16384;
        ::setrlimit(RLIMIT_FSIZE, &limit);
        try {
            oas::image::writeExr(path, noise, {{"oas.spp", "1"}});
        } catch (const std::runtime_error& e) {
            std::fprintf(stderr, "%s\n", e.what());
            std::_Exit(std::string(e.what()).find(path) != std::string::npos && dir.entries().empty() ? 0 : 3);
        }
        std::_Exit(4);
    };
    EXPECT_EXIT(writeWithLimit(), ::testing::ExitedWithCode(0), "cannot write .*full.exr");
    EXPECT_TRUE(dir.entries().empty());
}

TEST(Exr, RejectsMalformedImagesAndReservedAttributes)
{
    TempDir dir;
    Image bad(2, 2);
    bad.rgba.pop_back();
    EXPECT_THROW(oas::image::writeExr(dir / "a.exr", bad, {}), std::invalid_argument);
    EXPECT_THROW(oas::image::writeExr(dir / "b.exr", Image(0, 4), {}), std::invalid_argument);
    EXPECT_THROW(oas::image::writeExr(dir / "c.exr", Image(2, 2), {{"channels", "x"}}), std::invalid_argument);
    EXPECT_THROW(oas::image::writeExr(dir / "d.exr", Image(2, 2), {{"", "x"}}), std::invalid_argument);
    EXPECT_TRUE(dir.entries().empty());
}

// ---------------------------------------------------------------------------------------------
// PNG previews

/// The sRGB encoding of a linear value, from IEC 61966-2-1, computed independently of the library.
int expectedSrgb8(double linear)
{
    if (std::isnan(linear) || linear <= 0) return 0;
    if (linear >= 1) return 255;
    const double encoded = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
    return int(std::floor(encoded * 255 + 0.5));
}

std::vector<unsigned char> decodePng(const std::string& bytes, int& w, int& h)
{
    int comp = 0;
    unsigned char* data =
        stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()), int(bytes.size()), &w, &h, &comp, 3);
    if (!data) return {};
    std::vector<unsigned char> out(data, data + std::size_t(w) * h * 3);
    stbi_image_free(data);
    return out;
}

TEST(Png, KnownValuesMapToSrgb)
{
    // Anchors worked out by hand: linear 0.5 -> 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 187.5 -> 188;
    // 0.002 is on the linear segment: 12.92 * 0.002 * 255 = 6.59 -> 7.
    EXPECT_EQ(expectedSrgb8(0.5), 188);
    EXPECT_EQ(expectedSrgb8(0.002), 7);
    EXPECT_EQ(oas::image::linearToSrgb8(0.5f), 188);
    EXPECT_EQ(oas::image::linearToSrgb8(0.125f, 2.0f), 188);  // two stops up
    EXPECT_EQ(oas::image::linearToSrgb8(2.0f, -2.0f), 188);   // one stop down
    for (int i = 0; i <= 1000; ++i) {
        const float v = float(i) / 1000.0f;
        ASSERT_EQ(int(oas::image::linearToSrgb8(v)), expectedSrgb8(v)) << v;
    }

    const float values[] = {0.5f,  0.002f, 0.0f, 1.0f,  2.0f,      -1.0f, std::numeric_limits<float>::quiet_NaN(),
                            0.18f, 0.01f,  0.9f, 1e-6f, 0.0031308f};
    Image image(4, 3);  // 12 pixels; each pixel's R is values[p], G and B are 0.5 and 0.25
    for (std::size_t p = 0; p < 12; ++p) {
        image.rgba[p * 4 + 0] = values[p];
        image.rgba[p * 4 + 1] = 0.5f;
        image.rgba[p * 4 + 2] = 0.25f;
        image.rgba[p * 4 + 3] = 0.0f;  // alpha is not written
    }
    TempDir dir;
    const std::string path = dir / "preview.png";
    oas::image::writePngPreview(path, image);
    const std::string bytes = readBytes(path);
    EXPECT_EQ(bytes, oas::image::encodePngPreview(image));
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"preview.png"});

    ASSERT_GE(bytes.size(), 33u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_EQ(bytes.substr(12, 4), "IHDR");
    auto be32 = [&](std::size_t at) {
        return (std::uint32_t(std::uint8_t(bytes[at])) << 24) | (std::uint32_t(std::uint8_t(bytes[at + 1])) << 16) |
               (std::uint32_t(std::uint8_t(bytes[at + 2])) << 8) | std::uint32_t(std::uint8_t(bytes[at + 3]));
    };
    EXPECT_EQ(be32(16), 4u);                // width
    EXPECT_EQ(be32(20), 3u);                // height
    EXPECT_EQ(std::uint8_t(bytes[24]), 8);  // bit depth

    int w = 0, h = 0;
    const auto rgb = decodePng(bytes, w, h);
    ASSERT_EQ(w, 4);
    ASSERT_EQ(h, 3);
    for (std::size_t p = 0; p < 12; ++p) {
        EXPECT_EQ(int(rgb[p * 3 + 0]), expectedSrgb8(values[p])) << "pixel " << p << " value " << values[p];
        EXPECT_EQ(int(rgb[p * 3 + 1]), 188);
        EXPECT_EQ(int(rgb[p * 3 + 2]), expectedSrgb8(0.25));
    }
    EXPECT_EQ(int(rgb[0]), 188);

    // Exposure +1 stop doubles linear values before encoding.
    const auto brighter = decodePng(oas::image::encodePngPreview(image, 1.0f), w, h);
    EXPECT_EQ(int(brighter[0]), 255);                      // 0.5 * 2 = 1
    EXPECT_EQ(int(brighter[2]), expectedSrgb8(0.5));       // B 0.25 * 2
    EXPECT_EQ(int(brighter[7 * 3]), expectedSrgb8(0.36));  // 0.18 * 2
}

TEST(Png, FailedWriteNamesThePath)
{
    TempDir dir;
    const std::string path = dir / "no/dir/p.png";
    try {
        oas::image::writePngPreview(path, Image(2, 2));
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    EXPECT_TRUE(dir.entries().empty());
    EXPECT_THROW(oas::image::writePngPreview(dir / "e.png", Image(0, 0)), std::invalid_argument);
    EXPECT_TRUE(dir.entries().empty());
}

// ---------------------------------------------------------------------------------------------
// Metrics

void expectRelNear(double actual, double expected, const char* what)
{
    EXPECT_NEAR(actual, expected, 1e-12 * std::abs(expected) + 1e-300) << what;
}

TEST(Metrics, ConstantImages)
{
    const float r = 0.5f, i = 0.75f;  // exact in binary: d = 0.25
    const double d = 0.25, eps = 1e-2;
    const auto m = oas::image::compare(Image(5, 3, i, i, i, 0.0f), Image(5, 3, r, r, r, 1.0f));
    EXPECT_EQ(m.pixels, 15u);
    expectRelNear(m.mse, d * d, "mse");
    expectRelNear(m.relMse, d * d / (0.25 + eps), "relMse");
    expectRelNear(m.rmse, d, "rmse");

    // Another epsilon, and per-channel references: R ref 0 (error 0.1), G ref 1 (error -0.5), B exact.
    const auto m2 = oas::image::compare(Image(2, 2, 0.125f, 0.5f, 2.0f), Image(2, 2, 0.0f, 1.0f, 2.0f), {}, 0.5);
    expectRelNear(m2.mse, (0.125 * 0.125 + 0.25 + 0) / 3, "mse2");
    expectRelNear(m2.relMse, (0.125 * 0.125 / 0.5 + 0.25 / 1.5 + 0) / 3, "relMse2");
    expectRelNear(m2.rmse, std::sqrt((0.125 * 0.125 + 0.25) / 3), "rmse2");

    const auto same = oas::image::compare(Image(3, 3, 1, 2, 3), Image(3, 3, 1, 2, 3));
    EXPECT_EQ(same.mse, 0.0);
    EXPECT_EQ(same.relMse, 0.0);
    EXPECT_EQ(same.rmse, 0.0);
}

TEST(Metrics, CropSelectsTheRightPixels)
{
    // Reference 0; the image's R at (x, y) is x + 10 y, G and B 0, alpha random.
    Image image(8, 6), reference(8, 6);
    for (std::uint32_t y = 0; y < 6; ++y)
        for (std::uint32_t x = 0; x < 8; ++x) {
            image.pixel(x, y)[0] = float(x + 10 * y);
            image.pixel(x, y)[3] = float(x * y);
        }
    // Crop x=2..4, y=1..2: R values 12 13 14 / 22 23 24.
    const double sumSq = 144 + 169 + 196 + 484 + 529 + 576;
    const auto m = oas::image::compare(image, reference, Crop{2, 1, 3, 2});
    EXPECT_EQ(m.pixels, 6u);
    expectRelNear(m.mse, sumSq / 18, "crop mse");
    expectRelNear(m.relMse, sumSq / 1e-2 / 18, "crop relMse");  // reference 0: (I-R)^2 / eps

    const auto one = oas::image::compare(image, reference, Crop{7, 5, 1, 1}, 1.0);
    expectRelNear(one.mse, 57.0 * 57.0 / 3, "corner mse");
    expectRelNear(one.relMse, 57.0 * 57.0 / 3, "corner relMse");

    const auto whole = oas::image::compare(image, reference, Crop{0, 0, 8, 6});
    const auto implicitWhole = oas::image::compare(image, reference);
    EXPECT_EQ(whole.mse, implicitWhole.mse);
    EXPECT_EQ(whole.pixels, 48u);

    EXPECT_THROW(oas::image::compare(image, reference, Crop{6, 0, 3, 1}), std::invalid_argument);
    EXPECT_THROW(oas::image::compare(image, reference, Crop{0, 5, 1, 2}), std::invalid_argument);
    EXPECT_THROW(oas::image::compare(image, reference, Crop{0, 0, 0, 1}), std::invalid_argument);
    EXPECT_THROW(oas::image::compare(image, reference, Crop{0xffffffffu, 0, 2, 1}), std::invalid_argument);
    EXPECT_THROW(oas::image::compare(image, reference, {}, 0.0), std::invalid_argument);
    EXPECT_THROW(oas::image::compare(image, reference, {}, -1.0), std::invalid_argument);
}

TEST(Metrics, SizeMismatchThrowsNamingSizes)
{
    try {
        oas::image::compare(Image(4, 3), Image(4, 2));
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("4x3"), std::string::npos) << what;
        EXPECT_NE(what.find("4x2"), std::string::npos) << what;
    }
    EXPECT_THROW(oas::image::falseColourError(Image(4, 3), Image(3, 4)), std::invalid_argument);
    Image broken(2, 2);
    broken.rgba.resize(3);
    EXPECT_THROW(oas::image::compare(broken, Image(2, 2)), std::invalid_argument);
}

double luminance(const std::array<float, 3>& c)
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

TEST(Metrics, ErrorRampIsOrderedInLightness)
{
    double previous = -1;
    for (int i = 0; i <= 200; ++i) {
        const auto c = oas::image::errorRamp(i / 200.0);
        for (float v : c) {
            EXPECT_GE(v, 0.0f);
            EXPECT_LE(v, 1.0f);
        }
        const double y = luminance(c);
        EXPECT_GT(y, previous) << "t = " << i / 200.0;
        previous = y;
        EXPECT_FALSE(c == oas::image::kNonFiniteErrorColour);
    }
    EXPECT_LT(luminance(oas::image::errorRamp(0)), 0.02);
    EXPECT_GT(luminance(oas::image::errorRamp(1)), 0.8);
}

TEST(Metrics, FalseColourMapsLogErrorToTheRamp)
{
    // Reference 1 everywhere, eps 0 in effect negligible: set eps tiny so e = d^2 / (1 + eps) ~ d^2.
    oas::image::FalseColourOptions options;
    options.relEpsilon = 1e-12;
    Image reference(5, 1, 1, 1, 1), image(5, 1, 1, 1, 1);
    const float d[5] = {0.0f, 1e-4f, 0.1f, 100.0f, 0.0f};  // e = 0, 1e-8 (below 1e-5), 1e-2 (mid), 1e4 (above 10)
    for (int x = 0; x < 5; ++x)
        for (int c = 0; c < 3; ++c) image.pixel(x, 0)[c] = 1.0f + d[x];
    image.pixel(4, 0)[1] = std::numeric_limits<float>::quiet_NaN();
    const Image out = oas::image::falseColourError(image, reference, options);
    ASSERT_EQ(out.width, 5u);
    auto colour = [&](int x) { return std::array<float, 3>{out.pixel(x, 0)[0], out.pixel(x, 0)[1], out.pixel(x, 0)[2]}; };
    const auto low = oas::image::errorRamp(0), mid = oas::image::errorRamp(0.5), high = oas::image::errorRamp(1);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(colour(0)[c], low[c]);
        EXPECT_EQ(colour(1)[c], low[c]);
        EXPECT_NEAR(colour(2)[c], mid[c], 2e-3);  // log10(1e-2) = -2 is half way from -5 to 1
        EXPECT_EQ(colour(3)[c], high[c]);
    }
    EXPECT_TRUE(colour(4) == oas::image::kNonFiniteErrorColour);
    for (int x = 0; x < 5; ++x) EXPECT_EQ(out.pixel(x, 0)[3], 1.0f);

    options.minError = 0;
    EXPECT_THROW(oas::image::falseColourError(image, reference, options), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// oas-diff

struct ToolRun {
    int status = -1;
    std::string out, err, command;
};

std::string describe(const ToolRun& r)
{
    return "command: " + r.command + "\nstatus: " + std::to_string(r.status) + "\nstderr:\n" + r.err + "\nstdout:\n" + r.out;
}

/// Runs oas-diff with `args`, stdout and stderr going to files in `dir`.
ToolRun runDiff(const TempDir& dir, const std::vector<std::string>& args)
{
    ToolRun r;
    std::vector<std::string> argStrings = {OAS_DIFF_EXE};
    argStrings.insert(argStrings.end(), args.begin(), args.end());
    for (auto& a : argStrings) r.command += (r.command.empty() ? "" : " ") + a;
    std::vector<char*> argv;
    for (auto& a : argStrings) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string outPath = dir / "stdout.txt", errPath = dir / "stderr.txt";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
        r.err = std::string("posix_spawn: ") + std::strerror(rc);
        return r;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = readBytes(outPath);
    r.err = readBytes(errPath);
    fs::remove(outPath);
    fs::remove(errPath);
    return r;
}

/// The numbers on the table row whose region starts with `label`: pixels, MSE, relMSE, RMSE.
std::vector<double> rowNumbers(const std::string& out, const std::string& label)
{
    std::istringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
        if (line.rfind(label, 0) != 0) continue;
        std::istringstream fields(line.substr(label.size()));
        std::vector<double> v;
        double x;
        while (fields >> x) v.push_back(x);
        return v;
    }
    return {};
}

TEST(OasDiff, PrintsMetricsForWholeImageAndCrop)
{
    TempDir dir;
    // Reference 0.5 grey; the image is 0.75 everywhere except the 2x2 block at (1, 1), which is 1.5.
    Image reference(4, 3, 0.5f, 0.5f, 0.5f), image(4, 3, 0.75f, 0.75f, 0.75f);
    for (std::uint32_t y = 1; y < 3; ++y)
        for (std::uint32_t x = 1; x < 3; ++x)
            for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = 1.5f;
    const std::string a = dir / "a.exr", b = dir / "b.exr", png = dir / "err.png";
    oas::image::writeExr(a, image, {});
    oas::image::writeExr(b, reference, {});

    const ToolRun r = runDiff(dir, {a, b, "--crop", "1,1,2,2", "--error-png", png});
    ASSERT_EQ(r.status, 0) << describe(r);
    // Whole: 8 pixels with d = 0.25, 4 with d = 1.
    const double mse = (8 * 0.0625 + 4 * 1.0) / 12, rel = mse / (0.25 + 1e-2);
    const auto whole = rowNumbers(r.out, "whole 4x3");
    ASSERT_EQ(whole.size(), 4u) << describe(r);
    EXPECT_EQ(whole[0], 12);
    EXPECT_NEAR(whole[1], mse, 1e-8 * mse) << describe(r);
    EXPECT_NEAR(whole[2], rel, 1e-8 * rel) << describe(r);
    EXPECT_NEAR(whole[3], std::sqrt(mse), 1e-8) << describe(r);
    const auto crop = rowNumbers(r.out, "crop 1,1,2,2");
    ASSERT_EQ(crop.size(), 4u) << describe(r);
    EXPECT_EQ(crop[0], 4);
    EXPECT_NEAR(crop[1], 1.0, 1e-8);
    EXPECT_NEAR(crop[2], 1.0 / 0.26, 1e-8);
    EXPECT_NEAR(crop[3], 1.0, 1e-8);
    EXPECT_NE(r.out.find("region"), std::string::npos);

    const std::string pngBytes = readBytes(png);
    ASSERT_GE(pngBytes.size(), 8u);
    EXPECT_EQ(pngBytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    int w = 0, h = 0;
    EXPECT_EQ(decodePng(pngBytes, w, h).size(), 36u);
    EXPECT_EQ(w, 4);
    EXPECT_EQ(h, 3);

    // --epsilon changes relMSE only; without --crop there is no crop row.
    const ToolRun e = runDiff(dir, {a, b, "--epsilon", "0.75"});
    ASSERT_EQ(e.status, 0) << describe(e);
    const auto whole2 = rowNumbers(e.out, "whole 4x3");
    ASSERT_EQ(whole2.size(), 4u) << describe(e);
    EXPECT_NEAR(whole2[1], mse, 1e-8 * mse);
    EXPECT_NEAR(whole2[2], mse / 1.0, 1e-8);
    EXPECT_TRUE(rowNumbers(e.out, "crop").empty());
}

TEST(OasDiff, BadInputExitsWithStatus2)
{
    TempDir dir;
    const std::string a = dir / "a.exr", b = dir / "b.exr", small = dir / "small.exr";
    oas::image::writeExr(a, Image(4, 3, 1, 1, 1), {});
    oas::image::writeExr(b, Image(4, 3, 0, 0, 0), {});
    oas::image::writeExr(small, Image(3, 3, 0, 0, 0), {});
    const std::string missing = dir / "missing.exr";

    struct Case {
        std::vector<std::string> args;
        std::string mention;  ///< must appear on stderr
    };
    const std::vector<Case> cases = {
        {{missing, b}, missing},
        {{a, missing}, missing},
        {{a, b, "--crop", "1,2,3"}, "--crop must be x,y,w,h"},
        {{a, b, "--crop", "1,2,3,"}, "--crop must be x,y,w,h"},
        {{a, b, "--crop", "1,2,3,4,5"}, "--crop must be x,y,w,h"},
        {{a, b, "--crop", "a,b,c,d"}, "--crop must be x,y,w,h"},
        {{a, b, "--crop", "-1,0,1,1"}, "--crop must be x,y,w,h"},
        {{a, b, "--crop", "1, 2,3,4"}, "--crop must be x,y,w,h"},
        {{a, b, "--crop", "0,0,99999999999,1"}, "--crop must be x,y,w,h"},
        {{a, b, "--crop", "0,0,0,1"}, "at least 1"},
        {{a, b, "--crop", "3,0,2,1"}, "4x3"},  // outside the image
        {{a, small}, "3x3"},
        {{a, b, "--epsilon", "-1"}, "epsilon"},
        {{a, b, "--epsilon", "x"}, "epsilon"},
        {{a}, "REF"},
        {{a, b, "--bogus"}, "bogus"},
    };
    for (const auto& c : cases) {
        const ToolRun r = runDiff(dir, c.args);
        EXPECT_EQ(r.status, 2) << describe(r);
        EXPECT_TRUE(r.out.empty()) << describe(r);
        EXPECT_NE(r.err.find(c.mention), std::string::npos) << "expected '" << c.mention << "'\n" << describe(r);
    }

    // Regression (issue 8): a NaN pixel made oas-diff print "nan" and exit 0. Now: status 2, the
    // file and the pixels named. Infinities too, in either image.
    Image withNan(4, 3, 1, 1, 1), withInf(4, 3, 0, 0, 0);
    withNan.pixel(2, 1)[1] = std::numeric_limits<float>::quiet_NaN();
    withNan.pixel(3, 2)[0] = std::numeric_limits<float>::quiet_NaN();
    withInf.pixel(0, 2)[2] = -std::numeric_limits<float>::infinity();
    const std::string nanPath = dir / "nan.exr", infPath = dir / "inf.exr";
    oas::image::writeExr(nanPath, withNan, {});
    oas::image::writeExr(infPath, withInf, {});
    for (const auto& [args, mention] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{nanPath, b}, nanPath + ": 2 pixels hold NaN or infinite values, first at (2, 1)"},
             {{a, infPath}, infPath + ": 1 pixel holds NaN or infinite values, first at (0, 2) = [0, 0, -inf]"}}) {
        const ToolRun r = runDiff(dir, args);
        EXPECT_EQ(r.status, 2) << describe(r);
        EXPECT_TRUE(r.out.empty()) << describe(r);
        EXPECT_NE(r.err.find(mention), std::string::npos) << "expected '" << mention << "'\n" << describe(r);
    }
    fs::remove(nanPath);
    fs::remove(infPath);

    // An error PNG that cannot be written: status 1, the path named, nothing left behind.
    const std::string badPng = dir / "no/dir/err.png";
    const ToolRun r = runDiff(dir, {a, b, "--error-png", badPng});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find(badPng), std::string::npos) << describe(r);
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.exr", "b.exr", "small.exr"}));
}

}  // namespace
