// oas-view under a virtual X server (xvfb-run) on lavapipe, with the validation layer on: its
// screenshots (read back from the swapchain image the window shows) against oas-render's images
// and oas-samples' points, scripted keys, resizing and closing during a render, and what it says
// without a display. ViewGpu.* need Vulkan and xvfb-run: they say SKIPPED without them, and fail
// instead when OAS_REQUIRE_GPU=1 (scripts/test.sh, CI).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include "stb_image.h"

#include "view/points_view.hpp"
#include "view/text.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
    int status = -1;
    std::string output;
};

std::string readAll(const fs::path& p)
{
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

fs::path workDir(const std::string& name)
{
    const fs::path d = fs::path(OAS_VIEW_TEST_DIR) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

Result run(const std::string& command, const fs::path& dir)
{
    const fs::path log = dir / "output.txt";
    const std::string full = "cd '" + dir.string() + "' && " + command + " > '" + log.string() + "' 2>&1";
    const int status = std::system(full.c_str());
    Result r;
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.output = readAll(log);
    return r;
}

bool requireGpu()
{
    const char* v = std::getenv("OAS_REQUIRE_GPU");
    return v && std::string(v) == "1";
}

/// xvfb-run with its own display number per test (parallel ctest runs), a 24-bit screen large
/// enough for the points window, lavapipe unless a driver was chosen, and validation on.
std::string underXvfb(const std::string& args, int displayBase)
{
    std::string driver;
    if (!std::getenv("VK_DRIVER_FILES") && !std::getenv("VK_ICD_FILENAMES") &&
        fs::exists("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"))
        driver = "VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json "
                 "VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json ";
    return driver + "OAS_VK_VALIDATION=1 xvfb-run -a -n " + std::to_string(displayBase) + " -s '-screen 0 1600x1000x24' '" +
           std::string(OAS_VIEW_EXE) + "' " + args;
}

class ViewGpu : public ::testing::Test {
protected:
    void SetUp() override
    {
        if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
            if (requireGpu()) FAIL() << "xvfb-run is missing (scripts/setup.sh installs xvfb)";
            GTEST_SKIP() << "SKIPPED: no xvfb-run (install xvfb, or run scripts/setup.sh)";
        }
    }
    /// Runs oas-view and checks what every run must satisfy: exit 0 and no validation message.
    Result view(const std::string& args, const fs::path& dir, int display)
    {
        Result r = run(underXvfb(args, display), dir);
        if (r.status != 0 && r.output.find("no Vulkan") != std::string::npos && !requireGpu()) {
            skipped_ = true;
            return r;
        }
        EXPECT_EQ(r.status, 0) << r.output;
        EXPECT_EQ(r.output.find("oas::vk validation"), std::string::npos) << r.output;
        return r;
    }
    bool skipped_ = false;
};

/// Decoded RGB pixels of a PNG.
struct Picture {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
    const unsigned char* at(int x, int y) const { return rgb.data() + (std::size_t(y) * width + x) * 3; }
};

Picture decode(const fs::path& png)
{
    Picture p;
    int channels = 0;
    unsigned char* data = stbi_load(png.string().c_str(), &p.width, &p.height, &channels, 3);
    if (!data) return p;
    p.rgb.assign(data, data + std::size_t(p.width) * p.height * 3);
    stbi_image_free(data);
    return p;
}

std::string renderCommand(const std::string& args)
{
    return "'" + std::string(OAS_RENDER_EXE) + "' " + args;
}

template <class Image>
bool is(const Image& img, int x, int y, const std::uint8_t rgb[3])
{
    const auto* p = img.at(x, y);
    return p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2];
}

bool inPanel(const oas::view::PointsLayout& l, int x, int y)
{
    return x >= int(l.panelX) && y >= int(l.panelY) && x < int(l.panelX + l.panel) && y < int(l.panelY + l.panel);
}

/// The points panel of `img` shows a disc of radius r at each centre (a picture pixel): the
/// centre pixel and those up to r - 1 away along both axes (inside the panel) are the point
/// colour, and no point-coloured pixel of the panel lies further than r + 1 from every centre.
template <class Image>
void expectDiscs(const Image& img, const std::vector<std::pair<int, int>>& centres, double r, const oas::view::PointsLayout& l)
{
    ASSERT_GE(r, 1.0) << "a disc, not a pixel";
    for (const auto& [cx, cy] : centres) {
        EXPECT_TRUE(is(img, cx, cy, oas::view::kPointRgb)) << "centre " << cx << "," << cy;
        for (int d = 1; d <= int(r - 1); ++d)
            for (const auto& [dx, dy] : {std::pair{d, 0}, std::pair{-d, 0}, std::pair{0, d}, std::pair{0, -d}}) {
                if (!inPanel(l, cx + dx, cy + dy)) continue;  // the panel clips discs at its edges
                EXPECT_TRUE(is(img, cx + dx, cy + dy, oas::view::kPointRgb))
                    << "pixel " << dx << "," << dy << " from the centre " << cx << "," << cy << " is not lit";
            }
    }
    std::size_t stray = 0, lit = 0;
    for (int y = int(l.panelY); y < int(l.panelY + l.panel); ++y)
        for (int x = int(l.panelX); x < int(l.panelX + l.panel); ++x) {
            if (!is(img, x, y, oas::view::kPointRgb)) continue;
            ++lit;
            bool near = false;
            for (const auto& [cx, cy] : centres) near = near || std::hypot(x - cx, y - cy) <= r + 1;
            stray += !near;
        }
    EXPECT_EQ(stray, 0u) << "white pixels away from every point";
    EXPECT_GE(lit, centres.size() * 5) << "discs cover several pixels each";
}

/// How many pixels of the rectangle [x0, x1) x [y0, y1) have the colour rgb.
template <class Image>
std::size_t countColour(const Image& img, int x0, int y0, int x1, int y1, const std::uint8_t rgb[3])
{
    std::size_t n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) n += is(img, x, y, rgb);
    return n;
}

/// The rows above the panels that only the header labels use (the y axis's "1" reaches half a
/// line above the panel).
int headerBottom(const oas::view::PointsLayout& l)
{
    return int(l.panelY) - int(oas::view::textHeight(l.textScale));
}

/// The panel's frame, its ticks at 1/2, and text above the panels (the labels), below the panel
/// (x tick labels, axis name) and left of it (y tick labels, axis name).
template <class Image>
void expectLabelsAndFrame(const Image& img, const oas::view::PointsLayout& l)
{
    const int x0 = int(l.panelX), y0 = int(l.panelY), size = int(l.panel);
    const int w = int(l.width), h = int(l.height);
    EXPECT_EQ(countColour(img, x0 - 1, y0 - 1, x0 + size + 1, y0, oas::view::kFrameRgb), std::size_t(size + 2));
    EXPECT_EQ(countColour(img, x0 - 1, y0 - 1, x0, y0 + size + 1, oas::view::kFrameRgb), std::size_t(size + 2));
    EXPECT_TRUE(is(img, x0 + size / 2, y0 + size + 3, oas::view::kFrameRgb)) << "no tick at x = 1/2";
    EXPECT_TRUE(is(img, x0 - 4, y0 + size / 2, oas::view::kFrameRgb)) << "no tick at y = 1/2";
    EXPECT_GT(countColour(img, 0, 0, w, headerBottom(l), oas::view::kTextRgb), 0u) << "no labels above the panels";
    EXPECT_GT(countColour(img, x0, y0 + size + 1, x0 + size, h, oas::view::kTextRgb), 0u) << "no x axis labels";
    EXPECT_GT(countColour(img, 0, y0, x0 - 1, y0 + size, oas::view::kTextRgb), 0u) << "no y axis labels";
}

const std::string kScene = std::string(OAS_SOURCE_DIR) + "/scenes/cornell7d.json";

}  // namespace

TEST_F(ViewGpu, ConvergedScreenshotEqualsOasRenderImage)
{
    // Same scene, sampler, spp and seed: the viewer's passes (cut into smaller tiles) accumulate
    // exactly oas-render's sums, and the window shows image::srgb8 of them, the PNG's bytes.
    const fs::path dir = workDir("converged");
    const Result v = view("'" + kScene + "' --sampler bose --spp 16 --seed 7 --zoom 1 --screenshot shot.png", dir, 110);
    if (skipped_) GTEST_SKIP() << "SKIPPED: no Vulkan device";
    const Result r = run(renderCommand("'" + kScene + "' --sampler bose --spp 16 --seed 7 -o ref.exr"), dir);
    ASSERT_EQ(r.status, 0) << r.output;
    const Picture shot = decode(dir / "shot.png"), ref = decode(dir / "ref.png");
    ASSERT_GT(shot.width, 0) << v.output;
    ASSERT_EQ(shot.width, ref.width);
    ASSERT_EQ(shot.height, ref.height);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < shot.rgb.size(); ++i) differing += shot.rgb[i] != ref.rgb[i];
    EXPECT_EQ(differing, 0u) << "of " << shot.rgb.size() << " bytes";
    // Not a blank picture that would match anything blank.
    std::set<unsigned char> values(shot.rgb.begin(), shot.rgb.end());
    EXPECT_GT(values.size(), 50u);
}

TEST_F(ViewGpu, ScriptedKeysSwitchOffsetAndSppAndRestart)
{
    // o: cmj -> mj; - goes from 49 to Bose's largest count at most half that, 16 = 4^2 (the counts
    // 17 .. 24 are no squares); r restarts; the screenshot is oas-render's image of the new
    // settings, so the keys reached the renderer and the accumulation was cleared.
    const fs::path dir = workDir("keys");
    const Result v = view(
        "'" + kScene + "' --sampler bose --offset cmj --spp 49 --zoom 1 --script 'o@2 -@4 r@6' --screenshot shot.png", dir, 130);
    if (skipped_) GTEST_SKIP() << "SKIPPED: no Vulkan device";
    const Result r = run(renderCommand("'" + kScene + "' --sampler bose --offset mj --spp 16 -o ref.exr"), dir);
    ASSERT_EQ(r.status, 0) << r.output;
    const Picture shot = decode(dir / "shot.png"), ref = decode(dir / "ref.png");
    ASSERT_EQ(shot.rgb.size(), ref.rgb.size()) << v.output;
    EXPECT_TRUE(shot.rgb == ref.rgb) << "the scripted keys did not give bose mj at 16 spp";
    // And cmj at the same count gives a different picture (the comparison can fail).
    const Result before = run(renderCommand("'" + kScene + "' --sampler bose --offset cmj --spp 16 -o before.exr"), dir);
    ASSERT_EQ(before.status, 0) << before.output;
    EXPECT_FALSE(decode(dir / "before.png").rgb == shot.rgb);
}

TEST_F(ViewGpu, SamplerKeyMovesToTheNextSamplerThatFits)
{
    // s from bose at 16 spp: the next in the list is bush, which makes 16 = 4^2 at strength 2.
    const fs::path dir = workDir("sampler");
    const Result v = view("'" + kScene + "' --sampler bose --spp 16 --zoom 1 --script 's@2' --screenshot shot.png", dir, 150);
    if (skipped_) GTEST_SKIP() << "SKIPPED: no Vulkan device";
    const Result r = run(renderCommand("'" + kScene + "' --sampler bush --spp 16 -o ref.exr"), dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(decode(dir / "shot.png").rgb == decode(dir / "ref.png").rgb) << v.output;
}

TEST_F(ViewGpu, FaureStopsAtEveryCheckpointAndEndsAtOasRendersImage)
{
    // cornell7d draws 8 sample dimensions, so faure's base is 8 (the smallest prime power >= 8)
    // and at 100 spp (N = 8^3) its checkpoints are 8 = 8^1 and 64 = 8^2: the viewer must show
    // each (it prints a line with what the prefix guarantees when it does), in order, and none
    // else; and the segments between them must add up to oas-render's 100-spp image, byte for byte.
    const fs::path dir = workDir("faure");
    const Result v = view("'" + kScene + "' --sampler faure --spp 100 --seed 5 --zoom 1 --screenshot shot.png", dir, 210);
    if (skipped_) GTEST_SKIP() << "SKIPPED: no Vulkan device";
    const std::size_t first = v.output.find("checkpoint 8 spp: the first 8 of the sequence's 512 samples: the first 8 (1 x 8^1) are a (0,1,8)-net");
    const std::size_t second = v.output.find("checkpoint 64 spp: the first 64 of the sequence's 512 samples: the first 64 (1 x 8^2) are a (0,2,8)-net");
    EXPECT_NE(first, std::string::npos) << v.output;
    EXPECT_NE(second, std::string::npos) << v.output;
    EXPECT_LT(first, second) << v.output;
    std::size_t lines = 0;
    for (std::size_t at = v.output.find("oas-view: checkpoint"); at != std::string::npos; at = v.output.find("oas-view: checkpoint", at + 1))
        ++lines;
    EXPECT_EQ(lines, 2u) << v.output;
    const Result r = run(renderCommand("'" + kScene + "' --sampler faure --spp 100 --seed 5 -o ref.exr"), dir);
    ASSERT_EQ(r.status, 0) << r.output;
    const Picture shot = decode(dir / "shot.png"), ref = decode(dir / "ref.png");
    ASSERT_GT(shot.width, 0) << v.output;
    EXPECT_TRUE(shot.rgb == ref.rgb) << v.output;
}

TEST_F(ViewGpu, PointsModeDrawsOasSamplesPointsAsDiscsInEveryStratumOnce)
{
    // Bose, 121 points, 4 dims, pair (0, 1): a disc is centred on each of the points oas-samples
    // gives pixel (0, 0), no white pixel lies away from them, each of the 11 x 11 strata holds one,
    // and the labels and the frame around the panel are drawn.
    const fs::path dir = workDir("points");
    const Result v = view("--points --sampler bose --spp 121 --dims 4 --pair 0,1 --seed 3 --screenshot shot.png", dir, 170);
    if (skipped_) GTEST_SKIP() << "SKIPPED: no Vulkan device";
    const Result s = run("'" + std::string(OAS_SAMPLES_EXE) +
                             "' --sampler bose --spp 121 --dims 4 --seed 3 --pixel 0,0 --format csv -o pts.csv",
                         dir);
    ASSERT_EQ(s.status, 0) << s.output;
    const Picture shot = decode(dir / "shot.png");
    const auto layout = oas::view::pointsLayout(121, oas::view::kSpectrumRadius);
    ASSERT_EQ(shot.width, int(layout.width)) << v.output;
    ASSERT_EQ(shot.height, int(layout.height));
    const int size = int(layout.panel), x0 = int(layout.panelX), y0 = int(layout.panelY);
    std::vector<std::pair<int, int>> centres;  // picture pixels holding the points
    std::ifstream csv(dir / "pts.csv");
    std::string line;
    while (std::getline(csv, line)) {
        std::istringstream in(line);
        std::vector<std::string> cells;
        for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
        if (cells.size() < 2 || cells[0].find_first_not_of("0123456789.e-+") != std::string::npos) continue;
        const float x = std::stof(cells[0]), y = std::stof(cells[1]);  // dims 0 and 1
        centres.push_back({x0 + int(oas::view::pixelOf(x, size)), y0 + size - 1 - int(oas::view::pixelOf(y, size))});
    }
    ASSERT_EQ(centres.size(), 121u) << "read " << centres.size() << " points from oas-samples";
    expectDiscs(shot, centres, oas::view::pointRadius(121, layout.panel), layout);
    std::map<std::pair<int, int>, int> strata;
    for (const auto& [x, y] : centres) ++strata[{(x - x0) * 11 / size, (y0 + size - 1 - y) * 11 / size}];
    EXPECT_EQ(strata.size(), 121u);
    for (const auto& [cell, n] : strata) EXPECT_EQ(n, 1) << "cell " << cell.first << "," << cell.second;
    expectLabelsAndFrame(shot, layout);
}

TEST_F(ViewGpu, ResizingAndClosingDuringARenderAreClean)
{
    // z resizes the window twice (1x -> 2x -> 3x) while a long render runs, q closes it mid-render:
    // exit 0, no validation message, and the swapchain was rebuilt for the new sizes.
    const fs::path dir = workDir("resize");
    const Result v = view("'" + kScene + "' --spp 4096 --zoom 1 --script 'z@3 z@8 q@14'", dir, 190);
    if (skipped_) GTEST_SKIP() << "SKIPPED: no Vulkan device";
    EXPECT_NE(v.output.find("swapchain recreated"), std::string::npos) << v.output;
    EXPECT_EQ(v.output.find("swapchain recreated 0 time"), std::string::npos) << v.output;
}

TEST(View, WithoutADisplayItSaysSoAndExits2)
{
    const fs::path dir = workDir("nodisplay");
    const Result r = run("env -u DISPLAY -u WAYLAND_DISPLAY '" + std::string(OAS_VIEW_EXE) + "' '" + kScene + "'", dir);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("xvfb-run"), std::string::npos) << r.output;
}

TEST(View, BadArgumentsExit2AndSayWhy)
{
    const fs::path dir = workDir("badargs");
    const std::string exe = "env -u DISPLAY '" + std::string(OAS_VIEW_EXE) + "' ";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"'" + kScene + "' --script 'x@'", "--script"},
        {"'" + kScene + "' --script '#'", "unknown key"},
        {"--points --dims 4 --pair 0,9", "--pair"},
        {"--points --pair zero", "--pair"},
        {"'" + kScene + "' --points", "--points takes no scene"},
        {"", "give a scene file"},
        {"--points --sampler bose --spp 120", "bose"},
        {"'" + kScene + "' --reference '" + kScene + "'", "reference"},
        {"/no/such/scene.json", "scene.json"},
    };
    for (const auto& [args, says] : cases) {
        const Result r = run(exe + args, dir);
        EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(says), std::string::npos) << args << "\n" << r.output;
    }
}

TEST(ViewPoints, PanelAndPromiseFollowTheConstruction)
{
    EXPECT_EQ(oas::view::panelSize(121), 726u);
    EXPECT_EQ(oas::view::panelSize(1024), 768u);
    EXPECT_EQ(oas::view::panelSize(7), 763u);
    EXPECT_EQ(oas::view::pixelOf(0.0f, 726), 0u);
    EXPECT_EQ(oas::view::pixelOf(0.99999994f, 726), 725u);
    oas::Pattern p;
    p.construction = 1;  // Bose
    p.offset = 3;        // CMJ
    p.N = 121;
    p.s = 11;
    p.strength = 2;
    p.blockDims = 12;
    const auto same = oas::view::strataPromise(p, 0, 5);
    EXPECT_EQ(same.grid, 11u);
    EXPECT_TRUE(same.latinHypercube);
    const auto across = oas::view::strataPromise(p, 0, 12);
    EXPECT_EQ(across.grid, 0u);
    p.construction = 16;  // Random: no promise
    EXPECT_EQ(oas::view::strataPromise(p, 0, 1).grid, 0u);
    EXPECT_FALSE(oas::view::strataPromise(p, 0, 1).latinHypercube);
}

TEST(ViewPoints, PointsViewDrawsDiscsAxesAndLabels)
{
    // Three points of a 16-point set (the panel is 768 pixels): each a disc of pointRadius, not a
    // pixel; the frame and ticks around the panel; the labels where the layout leaves room.
    const std::vector<float> xs = {0.25f, 0.75f, 0.5f}, ys = {0.25f, 0.6f, 0.95f};
    const auto l = oas::view::pointsLayout(16, oas::view::kSpectrumRadius);
    ASSERT_GE(l.width, l.spectrumX + l.spectrum);
    ASSERT_GE(l.height, l.panelY + l.panel);
    const std::vector<double> power(std::size_t(2 * oas::view::kSpectrumRadius + 1) * (2 * oas::view::kSpectrumRadius + 1), 1.0);
    oas::view::PointsLabels labels;
    labels.header = "sampler test";
    labels.detail = "detail";
    labels.xAxis = "dim 0";
    labels.yAxis = "dim 1";
    labels.spectrum = "spectrum";
    labels.spectrumScale = "scale";
    const oas::view::Frame f =
        oas::view::drawPointsView(xs, ys, oas::view::StrataPromise{}, 16, power, oas::view::kSpectrumRadius, labels);
    ASSERT_EQ(f.width, l.width);
    ASSERT_EQ(f.height, l.height);
    std::vector<std::pair<int, int>> centres;
    for (std::size_t i = 0; i < xs.size(); ++i)
        centres.push_back({int(l.panelX + oas::view::pixelOf(xs[i], l.panel)),
                           int(l.panelY + l.panel - 1 - oas::view::pixelOf(ys[i], l.panel))});
    const double r = oas::view::pointRadius(16, l.panel);
    expectDiscs(f, centres, r, l);
    // Outside the disc, the panel stays black.
    for (const auto& [cx, cy] : centres) {
        const int away = int(std::ceil(r)) + 2;
        for (const auto& [dx, dy] : {std::pair{away, 0}, std::pair{-away, 0}, std::pair{0, away}, std::pair{0, -away}}) {
            const std::uint8_t black[3] = {0, 0, 0};
            EXPECT_TRUE(is(f, cx + dx, cy + dy, black)) << dx << "," << dy << " from " << cx << "," << cy;
        }
    }
    expectLabelsAndFrame(f, l);
    // The header says what it was given: another text gives other pixels, none gives none.
    labels.header = "sampler other";
    const auto other = oas::view::drawPointsView(xs, ys, {}, 16, power, oas::view::kSpectrumRadius, labels);
    EXPECT_FALSE(other.rgb == f.rgb);
    labels.header.clear();
    labels.detail.clear();
    const auto none = oas::view::drawPointsView(xs, ys, {}, 16, power, oas::view::kSpectrumRadius, labels);
    EXPECT_EQ(countColour(none, 0, 0, int(none.width), headerBottom(l), oas::view::kTextRgb), 0u);
}

TEST(ViewPoints, TextStaysInItsBox)
{
    // drawText's pixels lie inside textWidth x textHeight at the given corner, and there are some.
    oas::view::Frame f;
    f.resize(200, 60);
    const std::string text = "dim 12 (y) gp";
    const std::uint32_t scale = 2, w = oas::view::textWidth(text, scale), h = oas::view::textHeight(scale);
    ASSERT_GT(w, 0u);
    oas::view::drawText(f, 10, 20, text, oas::view::kTextRgb, scale);
    std::size_t inside = 0, outside = 0;
    for (std::uint32_t y = 0; y < f.height; ++y)
        for (std::uint32_t x = 0; x < f.width; ++x) {
            if (!is(f, int(x), int(y), oas::view::kTextRgb)) continue;
            (x >= 10 && x < 10 + w && y >= 20 && y < 20 + h ? inside : outside) += 1;
        }
    EXPECT_GT(inside, 20u);
    EXPECT_EQ(outside, 0u);
    // Turned upward, the same pixels fit the turned box: h wide, w tall, above (10, 20 + w).
    oas::view::Frame up;
    up.resize(60, 200);
    oas::view::drawText(up, 10, int(20 + w), text, oas::view::kTextRgb, scale, /*upward=*/true);
    std::size_t upInside = 0, upOutside = 0;
    for (std::uint32_t y = 0; y < up.height; ++y)
        for (std::uint32_t x = 0; x < up.width; ++x) {
            if (!is(up, int(x), int(y), oas::view::kTextRgb)) continue;
            (x >= 10 && x < 10 + h && y >= 20 && y < 20 + w ? upInside : upOutside) += 1;
        }
    EXPECT_EQ(upInside, inside);
    EXPECT_EQ(upOutside, 0u);
}
