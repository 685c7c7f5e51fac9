// oas-samples, the command-line tool, tested as a user runs it: a child process with captured
// stdout, stderr and exit status. Its output must be exactly the library's (CSV round-trips every
// float32, .npy holds the same bits), the GPU path must print the same bytes as the CPU path, and
// every bad argument must exit with status 2, say what was wrong on stderr and print nothing on
// stdout. The binary comes from the OAS_SAMPLES_EXE compile definition.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "oas/pattern.hpp"

#ifndef OAS_SAMPLES_EXE
#error "define OAS_SAMPLES_EXE as the path of the oas-samples binary"
#endif

extern char** environ;

namespace {

namespace fs = std::filesystem;

constexpr const char* kLavapipeIcd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

struct ToolRun {
    int status = -1;  ///< exit status, or 128 + signal
    std::string out, err;
    std::string command;  ///< for failure messages
};

std::string describe(const ToolRun& r)
{
    return "command: " + r.command + "\nstatus: " + std::to_string(r.status) + "\nstderr:\n" + r.err +
           "\nstdout (first 400 bytes):\n" + r.out.substr(0, 400);
}

/// Runs oas-samples with `args`; stdout and stderr are read concurrently (poll) so neither pipe
/// can fill up and stall the child. The child gets VK_DRIVER_FILES = lavapipe when the caller set
/// neither VK_DRIVER_FILES nor VK_ICD_FILENAMES. `env` entries ("NAME=value") replace or add to
/// the inherited environment.
ToolRun runTool(const std::vector<std::string>& args, const std::vector<std::string>& env = {})
{
    ToolRun r;
    std::vector<std::string> argStrings = {OAS_SAMPLES_EXE};
    argStrings.insert(argStrings.end(), args.begin(), args.end());
    for (auto& a : argStrings) r.command += (r.command.empty() ? "" : " ") + a;
    std::vector<char*> argv;
    for (auto& a : argStrings) argv.push_back(a.data());
    argv.push_back(nullptr);

    std::vector<std::string> envStrings;
    const auto overridden = [&](const std::string& entry) {
        const std::string name = entry.substr(0, entry.find('=') + 1);
        return std::any_of(env.begin(), env.end(), [&](const std::string& e) { return e.rfind(name, 0) == 0; });
    };
    for (char** e = environ; *e; ++e)
        if (!overridden(*e)) envStrings.emplace_back(*e);
    envStrings.insert(envStrings.end(), env.begin(), env.end());
    if (!std::getenv("VK_DRIVER_FILES") && !std::getenv("VK_ICD_FILENAMES"))
        envStrings.push_back(std::string("VK_DRIVER_FILES=") + kLavapipeIcd);
    std::vector<char*> envp;
    for (auto& e : envStrings) envp.push_back(e.data());
    envp.push_back(nullptr);

    int outPipe[2], errPipe[2];
    if (::pipe2(outPipe, O_CLOEXEC) != 0 || ::pipe2(errPipe, O_CLOEXEC) != 0) {
        r.err = std::string("pipe: ") + std::strerror(errno);
        return r;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, outPipe[1], 1);
    posix_spawn_file_actions_adddup2(&actions, errPipe[1], 2);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    pid_t pid = -1;
    const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    ::close(outPipe[1]);
    ::close(errPipe[1]);
    if (spawned != 0) {
        ::close(outPipe[0]);
        ::close(errPipe[0]);
        r.err = std::string("posix_spawn: ") + std::strerror(spawned);
        return r;
    }
    pollfd fds[2] = {{outPipe[0], POLLIN, 0}, {errPipe[0], POLLIN, 0}};
    std::string* sinks[2] = {&r.out, &r.err};
    int open = 2;
    char buf[65536];
    while (open > 0) {
        if (::poll(fds, 2, -1) < 0) {
            if (errno == EINTR) continue;
            break;
        }
        for (int i = 0; i < 2; ++i) {
            if (fds[i].fd < 0 || fds[i].revents == 0) continue;
            const ssize_t n = ::read(fds[i].fd, buf, sizeof buf);
            if (n > 0) {
                sinks[i]->append(buf, std::size_t(n));
            } else if (n == 0 || errno != EINTR) {
                ::close(fds[i].fd);
                fds[i].fd = -1;
                --open;
            }
        }
    }
    int wstatus = 0;
    while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {}
    r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 128 + WTERMSIG(wstatus);
    return r;
}

std::vector<std::string> splitLines(const std::string& text)
{
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

/// True when `token` occurs in `text` not glued to other digits (so "81" does not match "181").
bool hasNumber(const std::string& text, const std::string& token)
{
    for (std::size_t at = text.find(token); at != std::string::npos; at = text.find(token, at + 1)) {
        const bool before = at > 0 && std::isdigit(static_cast<unsigned char>(text[at - 1]));
        const std::size_t end = at + token.size();
        const bool after = end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]));
        if (!before && !after) return true;
    }
    return false;
}

std::uint32_t bits(float f)
{
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}

/// Parses CSV output: one line per point, exactly `dims` comma-separated floats per line.
std::vector<float> parseCsv(const std::string& text, std::uint32_t dims, std::string& error)
{
    std::vector<float> values;
    std::size_t lineNo = 0;
    for (const auto& line : splitLines(text)) {
        ++lineNo;
        const char* p = line.c_str();
        for (std::uint32_t d = 0; d < dims; ++d) {
            char* end = nullptr;
            errno = 0;
            const float v = std::strtof(p, &end);
            if (end == p || errno != 0) {
                error = "line " + std::to_string(lineNo) + ": bad number in '" + line + "'";
                return {};
            }
            values.push_back(v);
            const char want = d + 1 == dims ? '\0' : ',';
            if (*end != want) {
                error = "line " + std::to_string(lineNo) + ": expected " + std::to_string(dims) +
                        " comma-separated values, got '" + line + "'";
                return {};
            }
            p = end + (want ? 1 : 0);
        }
    }
    return values;
}

/// The library's own values for the request the tests pass to the tool.
std::vector<float> expectedValues(const std::string& sampler, std::uint32_t spp, std::uint32_t dims, std::uint32_t seed,
                                  std::uint32_t x, std::uint32_t y)
{
    oas::PatternRequest pr;
    pr.sampler = sampler;
    pr.spp = spp;
    pr.dims = dims;
    const oas::Pattern pattern = oas::makePattern(pr);
    oas::SampleRequest sr;
    sr.x0 = x;
    sr.y0 = y;
    sr.width = sr.height = 1;
    sr.spp = pattern.N;
    sr.dims = dims;
    sr.seed = seed;
    std::vector<float> values(std::size_t(sr.spp) * dims);
    oas::generateCpu(pattern, sr, values.data(), 1);
    return values;
}

void expectBitIdentical(const std::vector<float>& expected, const std::vector<float>& actual)
{
    ASSERT_EQ(expected.size(), actual.size());
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (bits(expected[i]) == bits(actual[i])) continue;
        if (++mismatches <= 5)
            ADD_FAILURE() << "value " << i << ": library " << expected[i] << " (0x" << std::hex << bits(expected[i]) << "), tool "
                          << actual[i] << " (0x" << bits(actual[i]) << std::dec << ")";
    }
    EXPECT_EQ(mismatches, 0u);
}

const std::vector<std::string> kSpecArgs = {"--sampler", "bose", "--spp", "49", "--dims", "5", "--seed", "7", "--pixel", "3,4"};

/// Each test gets a fresh empty directory for output files.
class CliTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        std::string pattern = (fs::temp_directory_path() / "oas_cli_test.XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr) << std::strerror(errno);
        dir_ = pattern;
    }
    void TearDown() override
    {
        std::error_code ec;
        if (!dir_.empty()) fs::remove_all(dir_, ec);
    }
    std::vector<std::string> entries() const
    {
        std::vector<std::string> names;
        for (auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
    fs::path dir_;
};

// ------------------------------------------------------------------------------------------ output

TEST_F(CliTest, CsvIsBitIdenticalToGenerateCpu)
{
    const ToolRun r = runTool(kSpecArgs);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(splitLines(r.out).size(), 49u) << describe(r);
    EXPECT_FALSE(r.out.empty() || r.out.back() != '\n') << "the last line must end with a newline";
    std::string error;
    const std::vector<float> values = parseCsv(r.out, 5, error);
    ASSERT_TRUE(error.empty()) << error << "\n" << describe(r);
    expectBitIdentical(expectedValues("bose", 49, 5, 7, 3, 4), values);
}

TEST_F(CliTest, PrintPatternGivesTheWordsInLayoutOrder)
{
    // --print-pattern is for hosts that upload the descriptor without linking oas: the "words"
    // array must be the 16 words of oas::makePattern, in order, and each named word must agree.
    const ToolRun r = runTool({"--sampler", "addelman-kempthorne", "--spp", "162", "--offset", "mj", "--print-pattern"});
    ASSERT_EQ(r.status, 0) << describe(r);
    oas::PatternRequest request;
    request.sampler = "addelman-kempthorne";
    request.spp = 162;
    request.offset = "mj";
    const oas::Pattern p = oas::makePattern(request);
    const std::uint32_t* words = &p.construction;
    std::string list;
    for (int i = 0; i < 16; ++i) list += (i ? ", " : "") + std::to_string(words[i]);
    EXPECT_NE(r.out.find("\"words\": [" + list + "]"), std::string::npos) << describe(r);
    EXPECT_NE(r.out.find("\"aux\": " + std::to_string(p.aux) + ","), std::string::npos) << describe(r);
    EXPECT_NE(r.out.find("\"recipShifts\": " + std::to_string(p.recipShifts) + "\n"), std::string::npos) << describe(r);
    const ToolRun bad = runTool({"--sampler", "bose", "--spp", "50", "--print-pattern"});
    EXPECT_EQ(bad.status, 2) << describe(bad);
    EXPECT_TRUE(bad.out.empty()) << describe(bad);
}

TEST_F(CliTest, CsvToFileMatchesStdout)
{
    const ToolRun toStdout = runTool(kSpecArgs);
    ASSERT_EQ(toStdout.status, 0) << describe(toStdout);
    const fs::path file = dir_ / "points.csv";
    std::vector<std::string> args = kSpecArgs;
    args.insert(args.end(), {"-o", file.string()});
    const ToolRun r = runTool(args);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(r.out.empty()) << "with -o nothing goes to stdout\n" << describe(r);
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(bytes, toStdout.out);
    EXPECT_EQ(entries(), std::vector<std::string>{"points.csv"}) << "a temporary file was left behind";
}

TEST_F(CliTest, NpyFileIsValidAndHoldsTheSameFloats)
{
    const fs::path file = dir_ / "points.npy";
    std::vector<std::string> args = kSpecArgs;
    args.insert(args.end(), {"--format", "npy", "-o", file.string()});
    const ToolRun r = runTool(args);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
    EXPECT_EQ(entries(), std::vector<std::string>{"points.npy"}) << "a temporary file was left behind";

    std::ifstream in(file, std::ios::binary);
    ASSERT_TRUE(in) << "cannot open " << file;
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GE(bytes.size(), 10u);
    EXPECT_EQ(bytes.substr(0, 6), std::string("\x93NUMPY", 6)) << "magic";
    EXPECT_EQ(int(static_cast<unsigned char>(bytes[6])), 1) << "major version";
    EXPECT_EQ(int(static_cast<unsigned char>(bytes[7])), 0) << "minor version";
    const std::size_t headerLen =
        std::size_t(static_cast<unsigned char>(bytes[8])) | std::size_t(static_cast<unsigned char>(bytes[9])) << 8;
    const std::size_t dataStart = 10 + headerLen;
    ASSERT_LE(dataStart, bytes.size());
    EXPECT_EQ(dataStart % 64, 0u) << "data must start at a multiple of 64 bytes (header length " << headerLen << ")";
    const std::string header = bytes.substr(10, headerLen);
    EXPECT_EQ(header.back(), '\n') << "header must end with a newline: '" << header << "'";
    EXPECT_EQ(header.front(), '{') << header;
    EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos) << header;
    EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
    EXPECT_NE(header.find("'shape': (49, 5)"), std::string::npos) << header;
    for (char c : header.substr(header.find('}') + 1, header.size() - header.find('}') - 2))
        EXPECT_EQ(c, ' ') << "padding after the dict must be spaces: '" << header << "'";

    ASSERT_EQ(bytes.size() - dataStart, 49u * 5u * sizeof(float)) << "data size";
    const std::uint32_t one = 1;
    ASSERT_EQ(*reinterpret_cast<const unsigned char*>(&one), 1) << "this test reads '<f4' as native floats";
    std::vector<float> values(49 * 5);
    std::memcpy(values.data(), bytes.data() + dataStart, values.size() * sizeof(float));
    expectBitIdentical(expectedValues("bose", 49, 5, 7, 3, 4), values);
}

/// A failed GPU run: a visible SKIPPED when there is no device (unless OAS_REQUIRE_GPU=1),
/// otherwise a failure that shows the run.
void failOrSkipWithoutDevice(const ToolRun& gpu)
{
    // The tool reports a missing device through vk::NoDeviceError's messages, exit status 1.
    const bool noDevice = gpu.status == 1 && (gpu.err.find("no usable Vulkan driver") != std::string::npos ||
                                              gpu.err.find("no Vulkan physical devices") != std::string::npos ||
                                              gpu.err.find("no Vulkan 1.1 device") != std::string::npos ||
                                              gpu.err.find("Vulkan loader is") != std::string::npos);
    const char* require = std::getenv("OAS_REQUIRE_GPU");
    const bool required = require && std::string(require) == "1";
    if (noDevice && !required) GTEST_SKIP() << "SKIPPED: no Vulkan device: " << gpu.err;
    FAIL() << (noDevice ? "no Vulkan device and OAS_REQUIRE_GPU=1\n" : "GPU run failed\n") << describe(gpu);
}

TEST_F(CliTest, GpuRunOnAFreshMachineIsQuiet)
{
    // Regression (issue 8): on a new machine (empty HOME) with XDG_CACHE_HOME set but empty, which
    // the XDG base-directory spec says means "unset", Mesa printed "Failed to create  for shader
    // cache" and the tool's stderr was no longer clean. Both spellings of a fresh cache must be quiet.
    const std::string home = (dir_ / "home").string();
    fs::create_directories(home);
    for (const std::vector<std::string>& env :
         {std::vector<std::string>{"HOME=" + home, "XDG_CACHE_HOME="}, {"HOME=" + home, "XDG_CACHE_HOME=relative/dir"}}) {
        std::vector<std::string> args = kSpecArgs;
        args.insert(args.end(), {"--device", "gpu"});
        const ToolRun gpu = runTool(args, env);
        if (gpu.status != 0) failOrSkipWithoutDevice(gpu);
        if (HasFailure() || IsSkipped()) return;
        EXPECT_TRUE(gpu.err.empty()) << env[1] << "\n" << describe(gpu);
    }
}

TEST_F(CliTest, RequestsTooLargeForMemorySayHowLarge)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "SKIPPED under AddressSanitizer: it needs more address space than the limit this test sets";
#else
    // Regression (issue 8): an in-range request that cannot be allocated ended in an uncaught
    // std::bad_alloc. 2^24 points x 64 dims is 4 GiB of float32: under a 1 GiB address-space limit
    // the tool must say how much it asked for, exit non-zero, and write nothing.
    const std::string out = (dir_ / "points.csv").string(), err = (dir_ / "err.txt").string();
    const std::string command = "ulimit -v 1048576; exec " + std::string(OAS_SAMPLES_EXE) +
                                " --sampler random --spp 16777216 --dims 64 -o '" + out + "' 2>'" + err + "' >/dev/null";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 1);
    std::ifstream in(err);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("out of memory for --spp 16777216 x --dims 64 = 1073741824 values (4.0 GiB"), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(out));
#endif
}

TEST_F(CliTest, GpuOutputIsByteIdenticalToCpu)
{
    const std::vector<std::vector<std::string>> cases = {
        kSpecArgs,
        {"--sampler", "addelman-kempthorne", "--spp", "50", "--dims", "13", "--seed", "3", "--pixel", "4000000000,17"},
        {"--sampler", "halton", "--spp", "20", "--dims", "40", "--pixel", "5,6"},
    };
    for (const auto& base : cases) {
        std::vector<std::string> cpuArgs = base, gpuArgs = base;
        cpuArgs.insert(cpuArgs.end(), {"--device", "cpu"});
        gpuArgs.insert(gpuArgs.end(), {"--device", "gpu"});
        const ToolRun cpu = runTool(cpuArgs);
        ASSERT_EQ(cpu.status, 0) << describe(cpu);
        const ToolRun gpu = runTool(gpuArgs);
        if (gpu.status != 0) failOrSkipWithoutDevice(gpu);
        if (HasFailure() || IsSkipped()) return;
        EXPECT_TRUE(gpu.err.empty()) << describe(gpu);
        EXPECT_EQ(gpu.out.size(), cpu.out.size()) << gpu.command;
        EXPECT_TRUE(gpu.out == cpu.out) << "GPU and CPU output differ for " << gpu.command;
    }
}

// ------------------------------------------------------------------------------------ bad input

struct BadCase {
    std::vector<std::string> args;
    std::vector<std::string> words;    ///< substrings stderr must contain
    std::vector<std::string> numbers;  ///< numbers stderr must contain as whole tokens
};

TEST_F(CliTest, BadArgumentsExitWithStatus2AndSayWhy)
{
    std::vector<std::string> samplerList = oas::samplerNames();
    std::vector<BadCase> cases = {
        {{"--sampler", "nope", "--spp", "16"}, {"nope"}, {}},
        {{"--sampler", "bose", "--spp", "100"}, {"bose"}, {"100", "81", "121"}},
        {{"--spp", "0"}, {"spp"}, {"0"}},
        {{"--sampler", "bose", "--spp", "0"}, {"spp"}, {"0"}},
        {{"--sampler", "bose", "--spp", "49", "--dims", "0"}, {"dims"}, {"0"}},
        {{"--sampler", "bose", "--spp", "49", "--dims", "5000"}, {"dims"}, {"5000"}},
        {{"--sampler", "bose", "--spp", "49", "--offset", "xyz"}, {"offset", "xyz"}, {}},
        {{"--sampler", "bose", "--spp", "49", "--pixel", "1"}, {"pixel", "'1'"}, {}},
        {{"--sampler", "bose", "--spp", "49", "--pixel", "-1,2"}, {"pixel", "-1,2"}, {}},
        {{"--sampler", "bose", "--spp", "49", "--format", "xml"}, {"format", "xml"}, {}},
        {{"--sampler", "bose", "--spp", "49", "--device", "tpu"}, {"device", "tpu"}, {}},
        {{"--sampler", "bose", "--spp", "49", "--bogus"}, {"--bogus"}, {}},
        {{"--sampler", "bose", "--spp", "49", "--strength", "3"}, {"bose", "strength"}, {"3"}},
    };
    // The unknown sampler's message lists every valid sampler.
    for (auto& name : samplerList) cases[0].words.push_back(name);
    for (const auto& c : cases) {
        const ToolRun r = runTool(c.args);
        SCOPED_TRACE(r.command);
        EXPECT_EQ(r.status, 2) << describe(r);
        EXPECT_TRUE(r.out.empty()) << "nothing may go to stdout on error\n" << describe(r);
        EXPECT_FALSE(r.err.empty()) << describe(r);
        for (auto& w : c.words) EXPECT_NE(r.err.find(w), std::string::npos) << "stderr lacks '" << w << "'\n" << describe(r);
        for (auto& n : c.numbers) EXPECT_TRUE(hasNumber(r.err, n)) << "stderr lacks the number " << n << "\n" << describe(r);
    }
}

TEST_F(CliTest, UnwritableOutputFailsNamesThePathAndLeavesNoFile)
{
    const std::string missing = "/nonexistent-dir/x.csv";
    ASSERT_FALSE(fs::exists("/nonexistent-dir")) << "the test needs /nonexistent-dir not to exist";
    {
        const ToolRun r = runTool({"--sampler", "bose", "--spp", "49", "-o", missing});
        EXPECT_NE(r.status, 0) << describe(r);
        EXPECT_NE(r.err.find(missing), std::string::npos) << describe(r);
        EXPECT_TRUE(r.out.empty()) << describe(r);
        EXPECT_FALSE(fs::exists(missing));
    }
    {
        // A missing directory inside our own directory: nothing at all may appear in it.
        const std::string path = (dir_ / "no-such-subdir" / "x.csv").string();
        const ToolRun r = runTool({"--sampler", "bose", "--spp", "49", "-o", path});
        EXPECT_NE(r.status, 0) << describe(r);
        EXPECT_NE(r.err.find(path), std::string::npos) << describe(r);
        EXPECT_TRUE(entries().empty()) << "left behind: " << ::testing::PrintToString(entries());
    }
    {
        // The target is an existing directory: the temporary file gets written, the rename fails,
        // and the temporary file must be removed again.
        fs::create_directory(dir_ / "taken");
        const std::string path = (dir_ / "taken").string();
        const ToolRun r = runTool({"--sampler", "bose", "--spp", "49", "-o", path});
        EXPECT_NE(r.status, 0) << describe(r);
        EXPECT_NE(r.err.find(path), std::string::npos) << describe(r);
        EXPECT_EQ(entries(), std::vector<std::string>{"taken"}) << "a temporary file was left behind";
        EXPECT_TRUE(fs::is_directory(dir_ / "taken"));
    }
}

// ------------------------------------------------------------------------------ other features

TEST_F(CliTest, RoundUpUsesTheNextValidSppAndSaysSo)
{
    const ToolRun r = runTool({"--sampler", "bose", "--spp", "100", "--round-up"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(splitLines(r.out).size(), 121u) << describe(r);
    EXPECT_NE(r.err.find("rounded up"), std::string::npos) << describe(r);
    EXPECT_TRUE(hasNumber(r.err, "121")) << describe(r);
    std::string error;
    const std::vector<float> values = parseCsv(r.out, 2, error);
    ASSERT_TRUE(error.empty()) << error;
    expectBitIdentical(expectedValues("bose", 121, 2, 0, 0, 0), values);
}

TEST_F(CliTest, ListNamesEverySamplerAndValidCounts)
{
    const ToolRun r = runTool({"--list", "--spp", "100", "--dims", "4"});
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> names = {"bose",    "bush",   "bose-bush",  "addelman-kempthorne",
                                            "cmjnd",   "random", "jittered2d", "cmj2d",
                                            "zerotwo", "halton", "sobol", "sobol-owen", "sobol-burley"};
    const std::vector<std::string> lines = splitLines(r.out);
    for (const auto& name : names) {
        bool found = false;
        for (const auto& line : lines) {
            std::istringstream words(line);
            std::string first;
            words >> first;
            found = found || first == name;
        }
        EXPECT_TRUE(found) << "no line starts with sampler '" << name << "'\n" << r.out;
    }
    // The bose entry is a pair of lines: the description, then the valid spp near 100.
    std::string bosePair;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        std::istringstream words(lines[i]);
        std::string first;
        words >> first;
        if (first == "bose") bosePair = lines[i] + "\n" + (i + 1 < lines.size() ? lines[i + 1] : "");
    }
    ASSERT_FALSE(bosePair.empty()) << r.out;
    EXPECT_TRUE(hasNumber(bosePair, "81")) << bosePair;
    EXPECT_TRUE(hasNumber(bosePair, "121")) << bosePair;
}

TEST_F(CliTest, SummaryReportsStratificationAndTheChoice)
{
    const ToolRun r = runTool({"--sampler", "oa", "--spp", "121", "--dims", "8", "--summary"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(splitLines(r.out).size(), 121u) << "--summary still prints the points on stdout";
    EXPECT_NE(r.err.find("chose bose"), std::string::npos) << describe(r);
    EXPECT_EQ(r.err.find("FAIL"), std::string::npos) << describe(r);
    std::size_t okLines = 0;
    for (const auto& line : splitLines(r.err)) {
        std::istringstream words(line);
        std::string first;
        words >> first;
        okLines += first == "ok";
    }
    EXPECT_GE(okLines, 3u) << "expected ok lines for range, 1D and 2D checks\n" << describe(r);
}

}  // namespace
