#include "penumbra/gpu/commands.hpp"

#include <algorithm>

#include "penumbra/core/error.hpp"

namespace penumbra::gpu {

namespace {
constexpr uint32_t kMaxStages = 127;  // timestamps per command list: one more than stages
constexpr uint32_t kMaxGroupsX = 32768;
}  // namespace

Pipeline::Pipeline(VkDevice device, VkShaderStageFlags push_stages, uint32_t push_bytes)
    : device_(device) {
  const VkPushConstantRange range{push_stages, 0, push_bytes};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.pushConstantRangeCount = 1;
  li.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(device_, &li, nullptr, &layout_), "vkCreatePipelineLayout");
}

Pipeline::~Pipeline() {
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
}

VkShaderModule Pipeline::module(std::span<const uint32_t> spirv) const {
  VkShaderModuleCreateInfo si{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  si.codeSize = spirv.size_bytes();
  si.pCode = spirv.data();
  VkShaderModule m = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device_, &si, nullptr, &m), "vkCreateShaderModule");
  return m;
}

ComputePipeline::ComputePipeline(VulkanContext& ctx, std::span<const uint32_t> spirv)
    : Pipeline(ctx.device(), VK_SHADER_STAGE_COMPUTE_BIT, kPushBytes) {
  VkShaderModule m = module(spirv);
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = m;
  ci.stage.pName = "main";
  ci.layout = layout_;
  const VkResult r = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline_);
  vkDestroyShaderModule(device_, m, nullptr);
  check(r, "compute pipeline creation");
}

CommandList::CommandList(VulkanContext& ctx) : ctx_(ctx) {
  VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qi.queryCount = kMaxStages + 1;
  check(vkCreateQueryPool(ctx.device(), &qi, nullptr, &queries_), "vkCreateQueryPool");
  vkResetQueryPool(ctx.device(), queries_, 0, kMaxStages + 1);
  cmd_ = ctx.begin_one_time();
  vkCmdWriteTimestamp2(cmd_, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_, 0);
}

CommandList::~CommandList() {
  if (!submitted_) {
    // Abandoned (an exception while recording): end and drop the command buffer unsubmitted.
    vkEndCommandBuffer(cmd_);
    ctx_.free_command_buffer(cmd_);
  }
  vkDestroyQueryPool(ctx_.device(), queries_, nullptr);
}

void CommandList::dispatch_raw(const ComputePipeline& pipe, const void* push, uint32_t bytes,
                               uint64_t threads) {
  if (threads == 0) return;
  const uint64_t groups = (threads + kGroupSize - 1) / kGroupSize;
  const uint64_t gx = std::min<uint64_t>(groups, kMaxGroupsX);
  const uint64_t gy = (groups + gx - 1) / gx;
  if (gy > 65535)
    throw Error("vulkan: dispatch of " + std::to_string(threads) + " threads is too large");
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.handle());
  vkCmdPushConstants(cmd_, pipe.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, bytes, push);
  vkCmdDispatch(cmd_, static_cast<uint32_t>(gx), static_cast<uint32_t>(gy), 1);
}

void CommandList::dispatch_groups_raw(const ComputePipeline& pipe, const void* push, uint32_t bytes,
                                      uint32_t groups) {
  if (groups == 0) return;
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.handle());
  vkCmdPushConstants(cmd_, pipe.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, bytes, push);
  const uint32_t gx = std::min(groups, kMaxGroupsX);
  vkCmdDispatch(cmd_, gx, (groups + gx - 1) / gx, 1);
}

void CommandList::barrier() {
  VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  mb.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  mb.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
  mb.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  mb.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
  VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  di.memoryBarrierCount = 1;
  di.pMemoryBarriers = &mb;
  vkCmdPipelineBarrier2(cmd_, &di);
}

void CommandList::fill(const Buffer& buffer, uint32_t value, size_t bytes) {
  vkCmdFillBuffer(cmd_, buffer.handle(), 0,
                  bytes == VK_WHOLE_SIZE ? VK_WHOLE_SIZE : (bytes + 3) / 4 * 4, value);
}

void CommandList::copy(const Buffer& src, const Buffer& dst, size_t bytes, size_t src_offset,
                       size_t dst_offset) {
  if (bytes == 0) return;
  const VkBufferCopy region{src_offset, dst_offset, bytes};
  vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &region);
}

void CommandList::mark(const std::string& name) {
  if (stages_.size() >= kMaxStages)
    throw Error("vulkan: too many timed stages in one command list");
  stages_.push_back(name);
  vkCmdWriteTimestamp2(cmd_, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_,
                       static_cast<uint32_t>(stages_.size()));
}

void CommandList::submit(StageTimes* times) {
  submitted_ = true;
  ctx_.end_one_time(cmd_);
  if (!times || stages_.empty()) return;
  std::vector<uint64_t> stamps(stages_.size() + 1);
  check(vkGetQueryPoolResults(ctx_.device(), queries_, 0, static_cast<uint32_t>(stamps.size()),
                              stamps.size() * sizeof(uint64_t), stamps.data(), sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  for (size_t s = 0; s < stages_.size(); ++s)
    times->add("gpu_" + stages_[s],
               static_cast<double>(stamps[s + 1] - stamps[s]) * ctx_.timestamp_period_ns() * 1e-6);
}

}  // namespace penumbra::gpu
