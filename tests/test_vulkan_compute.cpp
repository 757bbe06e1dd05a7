// The Vulkan backend's building blocks on a real device (lavapipe in CI): device selection,
// buffers, the GPU prefix sum and radix sort against std:: on random data, timestamps.
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <random>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/sort.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

TEST(VulkanCompute, BufferRoundTrip) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  gpu::VulkanContext& vk = backend.context();
  std::vector<uint32_t> data(12345);
  std::iota(data.begin(), data.end(), 7u);
  const gpu::Buffer b = vk.upload(data);
  EXPECT_NE(b.address(), 0u);
  EXPECT_EQ(vk.download<uint32_t>(b, data.size()), data);
  EXPECT_EQ(vk.download<uint32_t>(b, 3, 100), (std::vector<uint32_t>{107, 108, 109}));
  EXPECT_EQ(vk.validation_messages(), 0u);
}

TEST(VulkanCompute, PrefixSumMatchesStd) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  gpu::VulkanContext& vk = backend.context();
  std::mt19937 rng(3);
  // Sizes around the 1024-element blocks and a three-level hierarchy (> 1024² elements).
  for (uint32_t n : {1u, 1000u, 1024u, 1025u, 300000u, 1100000u}) {
    std::vector<uint32_t> data(n);
    for (uint32_t& x : data) x = rng() % 50;
    const gpu::Buffer b = vk.upload(data);
    std::deque<gpu::Buffer> scratch;
    StageTimes times;
    gpu::CommandList cl(vk);
    gpu::record_exclusive_scan(backend.programs(), cl, b, n, scratch);
    cl.mark("scan");
    cl.submit(&times);
    std::vector<uint32_t> expect(n);
    std::exclusive_scan(data.begin(), data.end(), expect.begin(), 0u);
    EXPECT_EQ(vk.download<uint32_t>(b, n), expect) << "n = " << n;
    EXPECT_GE(times.get("gpu_scan"), 0.0);
    EXPECT_EQ(times.stages().size(), 1u);
  }
  EXPECT_EQ(vk.validation_messages(), 0u);
}

/// Both block rankings: subgroup ballots (linear) and byte compares (the fallback).
void check_radix_sort(gpu::Backend& backend, gpu::RadixRanking ranking) {
  gpu::VulkanContext& vk = backend.context();
  std::mt19937 rng(5);
  for (int bits : {7, 14, 22}) {
    const uint32_t n = 70001;  // a partial last block
    std::vector<uint32_t> keys(n), vals(n);
    // Few distinct keys at 7 bits: long runs of equal keys test stability.
    for (uint32_t i = 0; i < n; ++i) keys[i] = rng() & ((1u << bits) - 1u), vals[i] = i;
    const gpu::Buffer k = vk.upload(keys), v = vk.upload(vals);
    const gpu::Buffer kt(vk, n * 4, gpu::Memory::device), vt(vk, n * 4, gpu::Memory::device);
    std::deque<gpu::Buffer> scratch;
    gpu::CommandList cl(vk);
    const bool in_place =
        gpu::record_radix_sort(backend.programs(), cl, k, v, kt, vt, n, bits, scratch, ranking);
    cl.submit();
    EXPECT_EQ(in_place, ((bits + 7) / 8) % 2 == 0);
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
    std::vector<uint32_t> sorted_keys(n);
    for (uint32_t i = 0; i < n; ++i) sorted_keys[i] = keys[order[i]];
    EXPECT_EQ(vk.download<uint32_t>(in_place ? k : kt, n), sorted_keys) << bits << " bits";
    EXPECT_EQ(vk.download<uint32_t>(in_place ? v : vt, n), order) << bits << " bits (stability)";
  }
  EXPECT_EQ(vk.validation_messages(), 0u);
}

TEST(VulkanCompute, RadixSortIsStableAndMatchesStd) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  if (backend.context().has_subgroup_ballot()) {
    check_radix_sort(backend, gpu::RadixRanking::ballot);
    return;
  }
  // Without ballots the ballot ranking is refused (best falls back to compare).
  gpu::VulkanContext& vk = backend.context();
  const gpu::Buffer b(vk, 1024, gpu::Memory::device);
  std::deque<gpu::Buffer> scratch;
  gpu::CommandList cl(vk);
  EXPECT_THROW(gpu::record_radix_sort(backend.programs(), cl, b, b, b, b, 256, 8, scratch,
                                      gpu::RadixRanking::ballot),
               Error);
}

TEST(VulkanCompute, RadixSortFallbackIsStableAndMatchesStd) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_radix_sort(backend, gpu::RadixRanking::compare);
}

TEST(VulkanCompute, DeviceSelection) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto devices = gpu::VulkanContext::list_devices();
  ASSERT_FALSE(devices.empty());
  // By index and by name: the same device.
  gpu::ContextOptions by_index;
  by_index.device = "0";
  EXPECT_EQ(gpu::VulkanContext(by_index).device_name(), devices[0].name);
  gpu::ContextOptions by_name;
  by_name.device = devices[0].name.substr(0, 4);
  EXPECT_FALSE(gpu::VulkanContext(by_name).device_name().empty());
  gpu::ContextOptions missing;
  missing.device = "no-such-gpu-name";
  try {
    gpu::VulkanContext ctx(missing);
    ADD_FAILURE() << "a device that does not exist was opened";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no device matches 'no-such-gpu-name'"), std::string::npos)
        << e.what();
  }
  EXPECT_GT(backend.context().timestamp_period_ns(), 0.0);
}

TEST(VulkanCompute, MethodsWithoutAVulkanPathAreRefused) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  EXPECT_TRUE(gpu::Backend::supports("gears"));
  EXPECT_TRUE(gpu::Backend::supports("silhouette_map"));
  EXPECT_FALSE(gpu::Backend::supports("exact"));
  try {
    backend.vulkan_method(MethodRegistry::builtin().get("exact"));
    ADD_FAILURE() << "exact has no Vulkan path";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has no Vulkan implementation"), std::string::npos);
  }
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanCompute, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
