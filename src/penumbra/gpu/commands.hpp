// Compute pipelines (SPIR-V embedded at build time, buffers passed as device addresses in push
// constants) and a command list that records dispatches, barriers and GPU timestamps, submits once
// and reports each stage's GPU time.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "penumbra/core/stats.hpp"
#include "penumbra/gpu/context.hpp"

namespace penumbra::gpu {

/// Threads per workgroup of every 1D compute shader (shaders/common.glsl: kGroupSize).
inline constexpr uint32_t kGroupSize = 256;
/// Push constants: at most 128 bytes (the minimum every Vulkan device guarantees).
inline constexpr uint32_t kPushBytes = 128;

/// A pipeline with its layout (one push-constant range, no descriptor sets), destroyed together.
class Pipeline {
 public:
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;
  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }

 protected:
  /// Creates the layout; the derived constructor creates pipeline_.
  Pipeline(VkDevice device, VkShaderStageFlags push_stages, uint32_t push_bytes);
  ~Pipeline();
  /// A shader module of `spirv` (the caller destroys it once the pipeline exists).
  VkShaderModule module(std::span<const uint32_t> spirv) const;

  VkDevice device_;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

class ComputePipeline : public Pipeline {
 public:
  ComputePipeline(VulkanContext& ctx, std::span<const uint32_t> spirv);
};

/// One command buffer: record, then submit() once and read the stage times.
class CommandList {
 public:
  explicit CommandList(VulkanContext& ctx);
  ~CommandList();
  CommandList(const CommandList&) = delete;
  CommandList& operator=(const CommandList&) = delete;

  VkCommandBuffer cmd() const { return cmd_; }

  /// Dispatches `threads` invocations of a 1D shader (groups of kGroupSize; more than 65535
  /// groups spill into y, the shader's global_id() folds them back).
  template <typename Push>
  void dispatch(const ComputePipeline& pipe, const Push& push, uint64_t threads) {
    static_assert(sizeof(Push) <= kPushBytes);
    dispatch_raw(pipe, &push, sizeof(Push), threads);
  }
  /// Dispatches exactly `groups` workgroups along x (shaders that own a block per group).
  template <typename Push>
  void dispatch_groups(const ComputePipeline& pipe, const Push& push, uint32_t groups) {
    static_assert(sizeof(Push) <= kPushBytes);
    dispatch_groups_raw(pipe, &push, sizeof(Push), groups);
  }
  /// Every earlier write visible to every later read or write (compute, transfer, graphics).
  void barrier();
  void fill(const Buffer& buffer, uint32_t value, size_t bytes = VK_WHOLE_SIZE);
  void copy(const Buffer& src, const Buffer& dst, size_t bytes, size_t src_offset = 0,
            size_t dst_offset = 0);
  /// Closes the stage that started at the previous mark (or at the start) under `name`.
  void mark(const std::string& name);

  /// Submits, waits, and adds "gpu_<stage>" times (ms, from the timestamps) to `times`.
  void submit(StageTimes* times = nullptr);

 private:
  void dispatch_raw(const ComputePipeline& pipe, const void* push, uint32_t bytes,
                    uint64_t threads);
  void dispatch_groups_raw(const ComputePipeline& pipe, const void* push, uint32_t bytes,
                           uint32_t groups);

  VulkanContext& ctx_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  std::vector<std::string> stages_;
  bool submitted_ = false;
};

}  // namespace penumbra::gpu
