// The Vulkan backend in tests: one device per test executable (validation layer on where
// installed; every test checks that it reported nothing), skipped where no device exists.
#pragma once

#ifdef PENUMBRA_HAVE_VULKAN

#include <gtest/gtest.h>

#include <memory>

#include "penumbra/gpu/backend.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra::test {

/// The shared backend, or nullptr when this machine has no Vulkan 1.3 device.
inline gpu::Backend* vulkan_backend() {
  static const std::unique_ptr<gpu::Backend> backend = []() -> std::unique_ptr<gpu::Backend> {
    if (!gpu::vulkan_available()) return nullptr;
    gpu::ContextOptions options;
    options.validation = true;
    return std::make_unique<gpu::Backend>(options);
  }();
  return backend.get();
}

/// Runs `method` of the frame on the GPU.
inline MethodResult run_vulkan(gpu::Backend& backend, const TestFrame& t, const std::string& method,
                               const std::map<std::string, std::string>& options = {},
                               bool want_masks = false) {
  const MethodInfo info = backend.vulkan_method(MethodRegistry::builtin().get(method));
  return t.frame->run(info, resolve_options(info, options), want_masks);
}

}  // namespace penumbra::test

/// Declares `backend` (gpu::Backend&) or skips the test when there is no Vulkan device.
#define PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend)                                            \
  gpu::Backend* backend##_ptr = ::penumbra::test::vulkan_backend();                         \
  if (!backend##_ptr) GTEST_SKIP() << "no Vulkan 1.3 device (install mesa-vulkan-drivers)"; \
  gpu::Backend& backend = *backend##_ptr

#endif  // PENUMBRA_HAVE_VULKAN
