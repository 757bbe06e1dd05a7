// The methods the viewer runs: the registry's on the CPU, or with `--backend vulkan` those with a
// Vulkan path, bound to one device. The workers run in parallel, so each GPU method is created and
// run holding the device's lock (one command stream at a time); the reference stays on the CPU.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "penumbra/shadows/registry.hpp"

namespace penumbra::gpu {
class Backend;
}

namespace penumbra::viewer {

class ViewerMethods {
 public:
  /// `backend`: "cpu" or "vulkan" (opens the device: Error when there is none, or when this build
  /// has no Vulkan backend); `device` as `render --vk-device`.
  ViewerMethods(const std::string& backend, const std::string& device);
  ~ViewerMethods();
  ViewerMethods(const ViewerMethods&) = delete;
  ViewerMethods& operator=(const ViewerMethods&) = delete;

  /// The method `name` as the method workers run it. Throws Error for an unknown name, or on the
  /// GPU for a method without a Vulkan path (naming those that have one).
  const MethodInfo& get(const std::string& name) const;
  /// The methods the menu lists.
  std::vector<const MethodInfo*> listed() const;
  /// "cpu", or the Vulkan device's name.
  const std::string& device_name() const { return device_name_; }
  bool gpu() const { return backend_ != nullptr; }

 private:
  std::unique_ptr<gpu::Backend> backend_;
  std::map<std::string, MethodInfo> bound_;  // name → the GPU method (map nodes do not move)
  std::shared_ptr<std::mutex> device_lock_ = std::make_shared<std::mutex>();
  std::string device_name_ = "cpu";
};

}  // namespace penumbra::viewer
