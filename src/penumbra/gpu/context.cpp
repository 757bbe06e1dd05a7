#include "penumbra/gpu/context.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "penumbra/core/error.hpp"

namespace penumbra::gpu {

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw Error(std::string("vulkan: ") + what + " failed (VkResult " + std::to_string(result) +
                ")");
}

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool env_flag(const char* name) {
  const char* v = std::getenv(name);
  return v &&
         (std::strcmp(v, "1") == 0 || std::strcmp(v, "on") == 0 || std::strcmp(v, "true") == 0);
}

bool has_layer(const char* name) {
  uint32_t n = 0;
  if (vkEnumerateInstanceLayerProperties(&n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
    return std::strcmp(l.layerName, name) == 0;
  });
}

bool has_instance_extension(const char* name) {
  uint32_t n = 0;
  if (vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> ext(n);
  vkEnumerateInstanceExtensionProperties(nullptr, &n, ext.data());
  return std::any_of(ext.begin(), ext.end(), [&](const VkExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
  });
}

std::string type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    default:
      return "other";
  }
}

VkInstance create_instance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "penumbra";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  std::vector<const char*> layers, extensions;
  if (validation) {
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  ci.enabledLayerCount = static_cast<uint32_t>(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  ci.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  if (vkCreateInstance(&ci, nullptr, &instance) != VK_SUCCESS) return VK_NULL_HANDLE;
  return instance;
}

/// Vulkan 1.3 devices with the features the shaders use, in enumeration order.
std::vector<VkPhysicalDevice> usable_devices(VkInstance instance) {
  uint32_t n = 0;
  if (vkEnumeratePhysicalDevices(instance, &n, nullptr) != VK_SUCCESS || n == 0) return {};
  std::vector<VkPhysicalDevice> all(n);
  vkEnumeratePhysicalDevices(instance, &n, all.data());
  std::vector<VkPhysicalDevice> out;
  for (VkPhysicalDevice d : all) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    if (p.apiVersion < VK_API_VERSION_1_3) continue;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f12.pNext = &f13;
    VkPhysicalDeviceFeatures2 f{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f.pNext = &f12;
    vkGetPhysicalDeviceFeatures2(d, &f);
    if (!f12.bufferDeviceAddress || !f13.dynamicRendering || !f13.synchronization2 ||
        !f13.maintenance4 || !f.features.shaderInt64)
      continue;
    if (!p.limits.timestampComputeAndGraphics) continue;
    out.push_back(d);
  }
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

VkPhysicalDevice choose_device(const std::vector<VkPhysicalDevice>& devices,
                               const std::string& selector) {
  auto name_of = [](VkPhysicalDevice d) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    return std::string(p.deviceName);
  };
  if (!selector.empty()) {
    const bool numeric = std::all_of(selector.begin(), selector.end(), [](char c) {
      return std::isdigit(static_cast<unsigned char>(c));
    });
    if (numeric) {
      // An index too large for size_t matches no device either (std::stoul threw "stoul").
      size_t i = 0;
      const auto [end, ec] = std::from_chars(selector.data(), selector.data() + selector.size(), i);
      if (ec == std::errc{} && end == selector.data() + selector.size() && i < devices.size())
        return devices[i];
    } else {
      for (VkPhysicalDevice d : devices)
        if (lower(name_of(d)).find(lower(selector)) != std::string::npos) return d;
    }
    std::string list;
    for (size_t i = 0; i < devices.size(); ++i)
      list += (i ? ", " : "") + std::to_string(i) + ": " + name_of(devices[i]);
    throw Error("vulkan: no device matches " + quote(selector, 40) + " (devices: " + list + ")");
  }
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    if (p.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) return d;
  }
  return devices.front();
}

}  // namespace

VkBool32 count_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                       VkDebugUtilsMessageTypeFlagsEXT,
                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* ctx = static_cast<VulkanContext*>(user);
  ++ctx->validation_messages_;
  std::fprintf(stderr, "penumbra: vulkan validation %s: %s\n",
               severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
               data && data->pMessage ? data->pMessage : "");
  return VK_FALSE;
}

// ---- Buffer

Buffer::Buffer(VulkanContext& ctx, size_t bytes, Memory memory)
    : device_(ctx.device()), bytes_(bytes) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = std::max<size_t>(bytes, 16);
  bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
             VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(device_, &bi, nullptr, &buffer_), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, buffer_, &req);
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.pNext = &flags;
  ai.allocationSize = req.size;
  if (memory == Memory::host) {
    // Cached where available: readbacks read every byte.
    ai.memoryTypeIndex =
        ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                VK_MEMORY_PROPERTY_HOST_COHERENT_BIT |
                                                VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    if (ai.memoryTypeIndex == UINT32_MAX)
      ai.memoryTypeIndex =
          ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                  VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  } else {
    ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (ai.memoryTypeIndex == UINT32_MAX)
      ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, 0);
  }
  if (ai.memoryTypeIndex == UINT32_MAX) {
    release();
    throw Error("vulkan: no memory type for a buffer");
  }
  if (vkAllocateMemory(device_, &ai, nullptr, &memory_) != VK_SUCCESS) {
    release();
    throw Error("vulkan: out of device memory allocating " + std::to_string(bytes >> 20) + " MiB");
  }
  check(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory");
  if (memory == Memory::host)
    check(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  VkBufferDeviceAddressInfo addr{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  addr.buffer = buffer_;
  address_ = vkGetBufferDeviceAddress(device_, &addr);
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    device_ = o.device_, buffer_ = o.buffer_, memory_ = o.memory_;
    address_ = o.address_, bytes_ = o.bytes_, mapped_ = o.mapped_;
    o.device_ = VK_NULL_HANDLE, o.buffer_ = VK_NULL_HANDLE, o.memory_ = VK_NULL_HANDLE;
    o.address_ = 0, o.bytes_ = 0, o.mapped_ = nullptr;
  }
  return *this;
}

Buffer::~Buffer() {
  release();
}

void Buffer::release() {
  if (device_ == VK_NULL_HANDLE) return;
  if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_) vkFreeMemory(device_, memory_, nullptr);
  buffer_ = VK_NULL_HANDLE, memory_ = VK_NULL_HANDLE, mapped_ = nullptr;
}

// ---- VulkanContext

std::vector<DeviceInfo> VulkanContext::list_devices() {
  std::vector<DeviceInfo> out;
  VkInstance instance = create_instance(false);
  if (!instance) return out;
  for (VkPhysicalDevice d : usable_devices(instance)) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    out.push_back({p.deviceName, type_name(p.deviceType), p.apiVersion});
  }
  vkDestroyInstance(instance, nullptr);
  return out;
}

VulkanContext::VulkanContext(const ContextOptions& options) {
#ifdef PENUMBRA_VK_VALIDATION_DEFAULT
  bool validation = true;
#else
  bool validation = options.validation || env_flag("PENUMBRA_VK_VALIDATION");
#endif
  validation = validation && has_layer(kValidationLayer) &&
               has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  instance_ = create_instance(validation);
  if (!instance_)
    throw Error(
        "vulkan: no Vulkan 1.3 loader or driver (install libvulkan1 and a driver, e.g. "
        "mesa-vulkan-drivers)");
  try {
    if (validation) {
      VkDebugUtilsMessengerCreateInfoEXT mi{
          VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
      mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
      mi.pfnUserCallback = count_message;
      mi.pUserData = this;
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      if (create)
        check(create(instance_, &mi, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
    }
    const std::vector<VkPhysicalDevice> devices = usable_devices(instance_);
    if (devices.empty())
      throw Error(
          "vulkan: no Vulkan 1.3 device with buffer device address, dynamic rendering and "
          "timestamps");
    std::string selector = options.device;
    if (selector.empty())
      if (const char* env = std::getenv("PENUMBRA_VK_DEVICE")) selector = env;
    physical_ = choose_device(devices, selector);

    VkPhysicalDeviceSubgroupProperties subgroup{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props2.pNext = &subgroup;
    vkGetPhysicalDeviceProperties2(physical_, &props2);
    const VkPhysicalDeviceProperties& props = props2.properties;
    info_ = {props.deviceName, type_name(props.deviceType), props.apiVersion};
    subgroup_size_ = subgroup.subgroupSize;
    subgroup_ballot_ = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                       (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_BALLOT_BIT) &&
                       subgroup.subgroupSize >= 8 && subgroup.subgroupSize <= 128;
    timestamp_period_ns_ = props.limits.timestampPeriod;
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> families(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nq, families.data());
    queue_family_ = UINT32_MAX;
    for (uint32_t i = 0; i < nq; ++i) {
      const VkQueueFlags need = VK_QUEUE_COMPUTE_BIT | VK_QUEUE_GRAPHICS_BIT;
      if ((families[i].queueFlags & need) == need && families[i].timestampValidBits > 0) {
        queue_family_ = i;
        break;
      }
    }
    if (queue_family_ == UINT32_MAX)
      throw Error("vulkan: no queue with graphics, compute and timestamps");

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = queue_family_;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f13.dynamicRendering = VK_TRUE;
    f13.synchronization2 = VK_TRUE;
    f13.maintenance4 = VK_TRUE;  // glslc's Vulkan 1.3 SPIR-V declares workgroup sizes by id
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.bufferDeviceAddress = VK_TRUE;
    f12.hostQueryReset = VK_TRUE;
    f12.pNext = &f13;
    VkPhysicalDeviceFeatures2 f{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f.features.shaderInt64 = VK_TRUE;
    VkPhysicalDeviceFeatures have;
    vkGetPhysicalDeviceFeatures(physical_, &have);
    // Optional: the exact depth pass, the depth-map lookups and shadow_volume run in the CPU's
    // double precision where it is available.
    f.features.shaderFloat64 = have.shaderFloat64;
    float64_ = have.shaderFloat64 == VK_TRUE;
    f.pNext = &f12;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.pNext = &f;
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    check(vkCreateDevice(physical_, &di, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = queue_family_;
    check(vkCreateCommandPool(device_, &pi, nullptr, &pool_), "vkCreateCommandPool");
  } catch (...) {
    destroy();
    throw;
  }
}

VulkanContext::~VulkanContext() {
  destroy();
}

void VulkanContext::destroy() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  device_ = VK_NULL_HANDLE, pool_ = VK_NULL_HANDLE, messenger_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
}

uint32_t VulkanContext::memory_type(uint32_t type_bits, VkMemoryPropertyFlags want) const {
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & want) == want) return i;
  return UINT32_MAX;
}

VkCommandBuffer VulkanContext::begin_one_time() {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  return cmd;
}

void VulkanContext::end_one_time(VkCommandBuffer cmd) {
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  check(vkCreateFence(device_, &fi, nullptr, &fence), "vkCreateFence");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  VkResult r = vkQueueSubmit(queue_, 1, &si, fence);
  if (r == VK_SUCCESS) r = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX);
  vkDestroyFence(device_, fence, nullptr);
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
  check(r, "queue submit");
}

void VulkanContext::free_command_buffer(VkCommandBuffer cmd) {
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
}

Buffer VulkanContext::upload(const void* data, size_t bytes) {
  Buffer dst(*this, bytes, Memory::device);
  if (bytes == 0) return dst;
  Buffer staging(*this, bytes, Memory::host);
  std::memcpy(staging.mapped(), data, bytes);
  submit_now([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(cmd, staging.handle(), dst.handle(), 1, &region);
  });
  return dst;
}

void VulkanContext::download(const Buffer& src, void* out, size_t bytes, size_t offset) {
  if (bytes == 0) return;
  Buffer staging(*this, bytes, Memory::host);
  submit_now([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, src.handle(), staging.handle(), 1, &region);
  });
  std::memcpy(out, staging.mapped(), bytes);
}

bool vulkan_available() {
  return !VulkanContext::list_devices().empty();
}

}  // namespace penumbra::gpu
