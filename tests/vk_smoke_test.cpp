// End-to-end check of the Vulkan host layer on whatever device the loader offers (lavapipe on CI),
// with the validation layer required, so API misuse fails the test instead of passing silently.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "vk/context.hpp"
#include "vk_smoke_spv.h"
#include "vk_texels_spv.h"

namespace {

using oas::vk::Buffer;
using oas::vk::ComputePipeline;
using oas::vk::Context;

std::unique_ptr<Context> makeValidatedContext()
{
    oas::vk::selectLavapipeIfUnset();
    oas::vk::ContextOptions opts;
    opts.validation = true;
    opts.requireValidation = true;
    return std::make_unique<Context>(opts);
}

#define OAS_MAKE_CONTEXT_OR_SKIP(var)                                                                                            \
    std::unique_ptr<Context> var;                                                                                                \
    try {                                                                                                                        \
        var = makeValidatedContext();                                                                                            \
    } catch (const oas::vk::NoDeviceError& e) {                                                                                  \
        GTEST_SKIP() << "SKIPPED: no Vulkan device: " << e.what();                                                               \
    }

/// Creates a buffer and the smoke pipeline, dispatches 64 elements, destroys both; returns the
/// last element (3 * 63 + 1 when the dispatch ran).
uint32_t dispatchSmall(Context& ctx)
{
    Buffer buf(ctx, 64 * sizeof(uint32_t));
    ComputePipeline pipe(ctx, vk_smoke_spv, sizeof(vk_smoke_spv), 1, 8);
    const uint32_t push[2] = {64, 1};
    Buffer* bufs[] = {&buf};
    ctx.dispatch(pipe, bufs, push, sizeof(push), 1);
    return static_cast<uint32_t*>(buf.data())[63];
}

TEST(VkSmoke, DispatchWritesEveryElement)
{
    OAS_MAKE_CONTEXT_OR_SKIP(ctx);
    ASSERT_TRUE(ctx->validationEnabled());
    std::printf("device: %s, driver: %s, lavapipe: %d\n", ctx->deviceName().c_str(), ctx->driverName().c_str(),
                int(ctx->isLavapipe()));

    constexpr uint32_t n = 100000;  // not a multiple of 64, so the bounds check in the shader matters
    {
        Buffer buf(*ctx, n * sizeof(uint32_t) + 256);  // slack past n must stay untouched
        auto* data = static_cast<uint32_t*>(buf.data());
        for (uint32_t i = 0; i < n + 64; ++i) data[i] = 0xDEADBEEFu;
        ComputePipeline pipe(*ctx, vk_smoke_spv, sizeof(vk_smoke_spv), 1, 8);
        for (uint32_t add : {7u, 1000u}) {  // second run checks descriptor-pool and fence reuse
            const uint32_t push[2] = {n, add};
            Buffer* bufs[] = {&buf};
            ctx->dispatch(pipe, bufs, push, sizeof(push), (n + 63) / 64);
            uint32_t bad = 0;
            for (uint32_t i = 0; i < n; ++i) bad += data[i] != i * 3u + add;
            EXPECT_EQ(bad, 0u) << "add=" << add << ", first element " << data[0];
            EXPECT_EQ(data[n], 0xDEADBEEFu);
        }
        EXPECT_THROW(ctx->dispatch(pipe, {}, nullptr, 0, 1), std::invalid_argument);
    }
    // Checked after the buffer and pipeline are gone, so their destruction is covered too.
    EXPECT_TRUE(ctx->validationMessages().empty());
    EXPECT_NO_THROW(oas::vk::throwIfValidationMessages(*ctx));  // on failure, gtest prints them all
}

TEST(VkSmoke, ASequenceDispatchesFromGroupCountsItsEarlierKernelsWrote)
{
    // One submission of four dispatches of the smoke kernel (data[i] = 3 i + add for i < n): the
    // first writes {1, 4, 7} into `counts`, the second runs from those group counts (1 x 4 x 7
    // groups; every group along y and z writes the same 64 values) and fills `data`, the third
    // writes {0, 3, 6}, and the fourth, sized by that, dispatches no group and leaves `data` as
    // it is. The second and fourth see what the first and third wrote only through the barriers
    // between the dispatches of a sequence.
    OAS_MAKE_CONTEXT_OR_SKIP(ctx);
    {
        Buffer counts(*ctx, 4 * sizeof(uint32_t)), data(*ctx, 64 * sizeof(uint32_t));
        ComputePipeline pipe(*ctx, vk_smoke_spv, sizeof(vk_smoke_spv), 1, 8);
        const auto step = [&](Buffer& target, uint32_t n, uint32_t add, Buffer* indirect) {
            oas::vk::SequencedDispatch d;
            d.pipeline = &pipe;
            d.buffers = {&target};
            d.push = {n, add};
            d.indirect = indirect;
            return d;
        };
        const oas::vk::SequencedDispatch sequence[] = {step(counts, 3, 1, nullptr), step(data, 64, 5, &counts),
                                                       step(counts, 3, 0, nullptr), step(data, 64, 9, &counts)};
        ctx->dispatchSequence(sequence);
        const auto* c = static_cast<const uint32_t*>(counts.data());
        EXPECT_EQ(c[0], 0u);
        EXPECT_EQ(c[1], 3u);
        const auto* values = static_cast<const uint32_t*>(data.data());
        uint32_t bad = 0;
        for (uint32_t i = 0; i < 64; ++i) bad += values[i] != 3 * i + 5;
        EXPECT_EQ(bad, 0u) << "data[0] = " << values[0] << ": 5 if the indirect dispatch ran once and the empty one not at all";
        oas::vk::SequencedDispatch outside = step(data, 64, 1, &counts);
        outside.indirectOffset = 8;  // three words from byte 8 run past the 16-byte buffer
        EXPECT_THROW(ctx->dispatchSequence({&outside, 1}), std::invalid_argument);
    }
    EXPECT_TRUE(ctx->validationMessages().empty());
    EXPECT_NO_THROW(oas::vk::throwIfValidationMessages(*ctx));
}

// The path tracer reads its scene records through texel buffers, and a BVH node carries its child
// index as float bits (a denormal) and shapes carry type ids: every bit pattern must arrive as it
// was written, NaN payloads and denormals included, not flushed or canonicalised.
TEST(VkSmoke, TexelBufferBindingCarriesEveryBitPattern)
{
    OAS_MAKE_CONTEXT_OR_SKIP(ctx);
    constexpr uint32_t texels = 1000;  // not a multiple of 64: the shader's bounds check matters
    {
        Buffer source(*ctx, texels * 16), copy(*ctx, texels * 16 + 16);
        auto* in = static_cast<uint32_t*>(source.data());
        const uint32_t special[] = {0x00000001u, 0x007fffffu, 0x80000001u, 0x7fc00001u, 0xffbfffffu,
                                    0x7f800000u, 0xff800000u, 0x80000000u, 0xffffffffu, 0x3f800000u};
        uint32_t state = 12345u;
        for (uint32_t i = 0; i < texels * 4; ++i) {
            state = state * 747796405u + 2891336453u;  // PCG's LCG step: every bit varies
            in[i] = i < std::size(special) ? special[i] : state;
        }
        auto* out = static_cast<uint32_t*>(copy.data());
        out[texels * 4] = 0xDEADBEEFu;
        ComputePipeline pipe(*ctx, vk_texels_spv, sizeof(vk_texels_spv), 2, 4, {},
                             {oas::vk::BindingKind::Uint4TexelBuffer, oas::vk::BindingKind::StorageBuffer});
        Buffer* bufs[] = {&source, &copy};
        ctx->dispatch(pipe, bufs, &texels, sizeof(texels), (texels + 63) / 64);
        uint32_t bad = 0;
        for (uint32_t i = 0; i < texels * 4; ++i) bad += out[i] != in[i];
        EXPECT_EQ(bad, 0u) << "first word " << std::hex << out[0] << " written as " << in[0];
        EXPECT_EQ(out[texels * 4], 0xDEADBEEFu);
    }
    EXPECT_NO_THROW(oas::vk::throwIfValidationMessages(*ctx));
}

TEST(VkSmoke, TexelBufferMisuseIsRejectedWithTheLimitNamed)
{
    OAS_MAKE_CONTEXT_OR_SKIP(ctx);
    Buffer ragged(*ctx, 20);  // not a whole number of 16-byte texels
    try {
        ragged.uint4View();
        ADD_FAILURE() << "a 20-byte buffer became a texel buffer";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("16-byte"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("maxTexelBufferElements"), std::string::npos) << e.what();
    }
    EXPECT_THROW(ComputePipeline(*ctx, vk_texels_spv, sizeof(vk_texels_spv), 2, 4, {}, {oas::vk::BindingKind::StorageBuffer}),
                 std::invalid_argument);
    EXPECT_NO_THROW(oas::vk::throwIfValidationMessages(*ctx));
}

TEST(VkSmoke, ValidationLogIsEmptyAfterFullLifecycle)
{
    OAS_MAKE_CONTEXT_OR_SKIP(ctx);
    EXPECT_EQ(dispatchSmall(*ctx), 63u * 3u + 1u);
    EXPECT_TRUE(ctx->validationMessages().empty());
    EXPECT_NO_THROW(oas::vk::throwIfValidationMessages(*ctx));
}

/// Sets an environment variable (or unsets it, for nullopt) for one scope.
class ScopedEnv {
public:
    ScopedEnv(const char* name, std::optional<std::string> value) : name_(name)
    {
        if (const char* old = std::getenv(name)) old_ = old;
        if (value)
            ::setenv(name, value->c_str(), 1);
        else
            ::unsetenv(name);
    }
    ~ScopedEnv()
    {
        if (old_)
            ::setenv(name_, old_->c_str(), 1);
        else
            ::unsetenv(name_);
    }

private:
    const char* name_;
    std::optional<std::string> old_;
};

// Regression (issue 8): on a machine whose HOME has no ~/.cache yet the layer reported, at info
// severity, that it could not open its shader validation cache, and every GPU test failed there
// while passing on machines that had run the tests before. A fresh HOME must give no finding, and
// the layer must not keep a cache file in the user's HOME for us.
TEST(VkSmoke, FreshHomeGivesNoValidationMessages)
{
    namespace fs = std::filesystem;
    std::string dir = (fs::temp_directory_path() / "oas-fresh-home-XXXXXX").string();
    ASSERT_NE(::mkdtemp(dir.data()), nullptr);
    {
        ScopedEnv home("HOME", dir), xdg("XDG_CACHE_HOME", std::nullopt);
        OAS_MAKE_CONTEXT_OR_SKIP(ctx);
        EXPECT_EQ(dispatchSmall(*ctx), 63u * 3u + 1u);
        EXPECT_TRUE(ctx->validationMessages().empty());
        EXPECT_NO_THROW(oas::vk::throwIfValidationMessages(*ctx));
    }
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().rfind("shader_validation_cache", 0), std::string::npos)
            << entry.path() << ": the layer wrote its validation cache into HOME";
    fs::remove_all(dir);
}

// Proves the messenger really collects: otherwise "no messages" above would prove nothing.
TEST(VkSmoke, ValidationCatchesMisuse)
{
    OAS_MAKE_CONTEXT_OR_SKIP(ctx);
    VkBufferCreateInfo bci{};
    bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    bci.size = 16;
    bci.usage = 0;  // invalid: at least one usage bit is required
    VkBuffer b = VK_NULL_HANDLE;
    if (vkCreateBuffer(ctx->device(), &bci, nullptr, &b) == VK_SUCCESS) vkDestroyBuffer(ctx->device(), b, nullptr);
    const auto msgs = ctx->validationMessages();
    ASSERT_FALSE(msgs.empty());
    EXPECT_NE(msgs.front().find("VkBufferCreateInfo-usage"), std::string::npos) << msgs.front();
    EXPECT_THROW(oas::vk::throwIfValidationMessages(*ctx), oas::vk::VulkanError);
    ctx->clearValidationMessages();
}

TEST(VkCheck, ErrorTextNamesCallResultAndLocation)
{
    EXPECT_STREQ(oas::vk::resultName(VK_ERROR_DEVICE_LOST), "VK_ERROR_DEVICE_LOST");
    EXPECT_STREQ(oas::vk::resultName(VK_ERROR_OUT_OF_DEVICE_MEMORY), "VK_ERROR_OUT_OF_DEVICE_MEMORY");
    auto fails = [] { return VK_ERROR_DEVICE_LOST; };
    try {
        OAS_VK_CHECK(fails());
        FAIL() << "OAS_VK_CHECK did not throw";
    } catch (const oas::vk::VulkanError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.result(), VK_ERROR_DEVICE_LOST);
        EXPECT_NE(what.find("fails()"), std::string::npos) << what;
        EXPECT_NE(what.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << what;
        EXPECT_NE(what.find("vk_smoke_test.cpp:"), std::string::npos) << what;
    }
    int calls = 0;
    OAS_VK_CHECK((++calls, VK_SUCCESS));
    EXPECT_EQ(calls, 1);  // evaluated exactly once
}

}  // namespace
