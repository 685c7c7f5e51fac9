#pragma once
// Shared Vulkan context for GPU tests. Lavapipe is selected when the caller has not chosen a
// driver; the validation layer is required and any message it prints fails the test. Without a
// device the tests say SKIPPED visibly, unless OAS_REQUIRE_GPU=1 (set by .ci/run), where a
// missing device is a failure: CI must never pass by skipping.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "vk/context.hpp"

namespace oas::test {

struct GpuState {
    std::unique_ptr<vk::Context> context;
    std::string error;
    std::vector<std::string> creationMessages;  ///< findings while the context was made
};

inline GpuState& gpuState()
{
    static GpuState state = [] {
        GpuState s;
        vk::selectLavapipeIfUnset();
        vk::ContextOptions options;
        options.validation = true;
        options.requireValidation = true;
        try {
            s.context = std::make_unique<vk::Context>(options);
            s.creationMessages = s.context->validationMessages();
        } catch (const vk::NoDeviceError& e) {
            s.error = e.what();
        }
        return s;
    }();
    return state;
}

/// Fixture: SetUp skips (visibly) or fails without a device; TearDown fails on validation output.
class GpuTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        GpuState& s = gpuState();
        if (!s.context) {
            const char* require = std::getenv("OAS_REQUIRE_GPU");
            if (require && std::string(require) == "1") FAIL() << "no Vulkan device and OAS_REQUIRE_GPU=1: " << s.error;
            GTEST_SKIP() << "SKIPPED: no Vulkan device: " << s.error;
        }
        // Context creation is checked too (every test reports it, since any one may run alone).
        for (const auto& m : s.creationMessages) ADD_FAILURE() << "Vulkan validation at context creation: " << m;
        s.context->clearValidationMessages();
    }
    void TearDown() override
    {
        GpuState& s = gpuState();
        if (!s.context) return;
        const auto messages = s.context->validationMessages();
        for (const auto& m : messages) ADD_FAILURE() << "Vulkan validation: " << m;
        s.context->clearValidationMessages();
    }
    vk::Context& context() { return *gpuState().context; }
};

}  // namespace oas::test
