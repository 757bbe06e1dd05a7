// The Vulkan backend in tests: one device per test executable (validation layer on where
// installed; every test checks that it reported nothing), skipped where no device exists.
#pragma once

#ifdef PENUMBRA_HAVE_VULKAN

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "penumbra/gpu/backend.hpp"
#include "penumbra/render/receivers.hpp"
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

/// |V_a − V_b| of light 0 over the active pixels (RGB channels too, where both have them).
struct VisibilityDiff {
  double max = 0.0, mean = 0.0;
  int active = 0;
  int between = 0;  // active pixels whose V_a lies in (lo, hi) (see visibility_diff)
};

inline VisibilityDiff visibility_diff(const TestFrame& t, const MethodResult& a,
                                      const MethodResult& b, float lo = 0.0f, float hi = 1.0f) {
  const Visibility& va = a.per_light[0];
  const Visibility& vb = b.per_light[0];
  VisibilityDiff d;
  double sum = 0.0;
  for (size_t i = 0; i < va.lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++d.active;
    d.between += va.lit[i] > lo && va.lit[i] < hi;
    double m = std::abs(static_cast<double>(va.lit[i]) - vb.lit[i]);
    sum += m;
    if (va.lit_rgb && vb.lit_rgb)
      for (int c = 0; c < 3; ++c)
        m = std::max(m, std::abs(static_cast<double>((*va.lit_rgb)[i][c]) - (*vb.lit_rgb)[i][c]));
    d.max = std::max(d.max, m);
  }
  d.mean = sum / std::max(1, d.active);
  return d;
}

}  // namespace penumbra::test

/// Declares `backend` (gpu::Backend&) or skips the test when there is no Vulkan device.
#define PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend)                                            \
  gpu::Backend* backend##_ptr = ::penumbra::test::vulkan_backend();                         \
  if (!backend##_ptr) GTEST_SKIP() << "no Vulkan 1.3 device (install mesa-vulkan-drivers)"; \
  gpu::Backend& backend = *backend##_ptr

#endif  // PENUMBRA_HAVE_VULKAN
