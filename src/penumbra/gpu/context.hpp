// The Vulkan 1.3 device Penumbra's GPU methods run on: headless (no surface, no swapchain), one
// queue with compute and graphics, buffers addressed by device address (no descriptor sets: every
// shader gets its buffers as 64-bit pointers in push constants).
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::gpu {

/// Throws penumbra::Error naming `what` when `result` is not VK_SUCCESS.
void check(VkResult result, const char* what);

struct ContextOptions {
  /// Which device: empty = $PENUMBRA_VK_DEVICE, else the first discrete GPU, else the first
  /// device. A number is an index into the list `penumbra info` prints; anything else is matched
  /// against the device names (case-insensitive substring).
  std::string device;
  /// Khronos validation layer (when installed): default on in debug builds and with
  /// $PENUMBRA_VK_VALIDATION=1; the tests turn it on. Each message is counted and printed.
  bool validation = false;
};

/// Where a buffer lives: device-local (shader data) or host-visible (upload, readback).
enum class Memory { device, host };

class VulkanContext;

/// A buffer with its own memory and device address. Move-only.
class Buffer {
 public:
  Buffer() = default;
  Buffer(VulkanContext& ctx, size_t bytes, Memory memory);
  Buffer(Buffer&& other) noexcept { *this = std::move(other); }
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer();

  VkBuffer handle() const { return buffer_; }
  VkDeviceAddress address() const { return address_; }
  size_t bytes() const { return bytes_; }
  void* mapped() const { return mapped_; }  // host buffers only

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceAddress address_ = 0;
  size_t bytes_ = 0;
  void* mapped_ = nullptr;
};

struct DeviceInfo {
  std::string name;
  std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
  uint32_t api_version = 0;
};

class VulkanContext {
 public:
  /// Opens the chosen device. Throws penumbra::Error (one line) when Vulkan or a Vulkan 1.3 device
  /// with the needed features is missing.
  explicit VulkanContext(const ContextOptions& options = {});
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  /// Every Vulkan 1.3 device on this machine (empty if there is no loader or no device).
  static std::vector<DeviceInfo> list_devices();

  VkDevice device() const { return device_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  const std::string& device_name() const { return info_.name; }
  const DeviceInfo& info() const { return info_; }
  double timestamp_period_ns() const { return timestamp_period_ns_; }
  /// Whether shaders may use double precision (shaderFloat64).
  bool has_float64() const { return float64_; }
  /// Whether compute shaders have subgroup ballots with 8 to 128 invocations per subgroup (the
  /// radix sort's linear ranking, radix_scatter.comp).
  bool has_subgroup_ballot() const { return subgroup_ballot_; }
  uint32_t subgroup_size() const { return subgroup_size_; }
  /// Validation messages (warnings and errors) reported so far; 0 without the layer.
  uint32_t validation_messages() const { return validation_messages_; }
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }

  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags want) const;

  /// Device-local buffer holding `bytes` of `data` (staged through a host buffer).
  Buffer upload(const void* data, size_t bytes);
  template <typename T>
  Buffer upload(const std::vector<T>& v) {
    return upload(v.data(), v.size() * sizeof(T));
  }
  /// Copies `bytes` from the start of device buffer `src` into host memory `out`.
  void download(const Buffer& src, void* out, size_t bytes, size_t offset = 0);
  template <typename T>
  std::vector<T> download(const Buffer& src, size_t count, size_t offset_elems = 0) {
    std::vector<T> out(count);
    if (count) download(src, out.data(), count * sizeof(T), offset_elems * sizeof(T));
    return out;
  }

  /// Records commands with `record` into a one-time command buffer and waits for them.
  template <typename Fn>
  void submit_now(Fn&& record) {
    VkCommandBuffer cmd = begin_one_time();
    record(cmd);
    end_one_time(cmd);
  }
  VkCommandBuffer begin_one_time();
  /// Submits `cmd`, waits for it and frees it.
  void end_one_time(VkCommandBuffer cmd);
  /// Frees a command buffer from begin_one_time() that is not submitted.
  void free_command_buffer(VkCommandBuffer cmd);

 private:
  friend VkBool32 count_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                VkDebugUtilsMessageTypeFlagsEXT,
                                const VkDebugUtilsMessengerCallbackDataEXT*, void*);
  void destroy();
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_{};
  DeviceInfo info_;
  double timestamp_period_ns_ = 1.0;
  bool float64_ = false;
  bool subgroup_ballot_ = false;
  uint32_t subgroup_size_ = 0;
  uint32_t validation_messages_ = 0;
};

/// Whether a Vulkan 1.3 device can be opened here (for tests that need one).
bool vulkan_available();

}  // namespace penumbra::gpu
