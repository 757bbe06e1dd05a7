#include "viewer_methods.hpp"

#include "penumbra/core/error.hpp"
#include "penumbra/shadows/method.hpp"
#ifdef PENUMBRA_HAVE_VULKAN
#include "penumbra/gpu/backend.hpp"
#endif

namespace penumbra::viewer {

namespace {

/// A GPU method run holding the device's lock.
class LockedMethod final : public ShadowMethod {
 public:
  LockedMethod(std::unique_ptr<ShadowMethod> inner, std::shared_ptr<std::mutex> lock)
      : inner_(std::move(inner)), lock_(std::move(lock)) {}
  Visibility compute(const ShadowContext& ctx) override {
    const std::lock_guard<std::mutex> hold(*lock_);
    return inner_->compute(ctx);
  }

 private:
  std::unique_ptr<ShadowMethod> inner_;
  std::shared_ptr<std::mutex> lock_;
};

}  // namespace

ViewerMethods::~ViewerMethods() = default;

#ifdef PENUMBRA_HAVE_VULKAN
ViewerMethods::ViewerMethods(const std::string& backend, const std::string& device) {
  if (backend == "cpu") return;
  gpu::ContextOptions options;
  options.device = device;
  backend_ = std::make_unique<gpu::Backend>(options);
  device_name_ = backend_->context().device_name();
  for (const std::string& name : gpu::Backend::methods()) {
    MethodInfo info = backend_->vulkan_method(MethodRegistry::builtin().get(name));
    info.create = [create = info.create, lock = device_lock_](const MethodOptions& o) {
      const std::lock_guard<std::mutex> hold(*lock);  // creating builds pipelines on the device
      return std::unique_ptr<ShadowMethod>(std::make_unique<LockedMethod>(create(o), lock));
    };
    bound_.emplace(name, std::move(info));
  }
}
#else
ViewerMethods::ViewerMethods(const std::string& backend, const std::string&) {
  if (backend != "cpu")
    throw Error(
        "--backend vulkan: this build has no Vulkan backend (install libvulkan-dev and glslc, "
        "then rebuild)");
}
#endif

const MethodInfo& ViewerMethods::get(const std::string& name) const {
  const MethodInfo& cpu = MethodRegistry::builtin().get(name);  // unknown → Error
  if (!gpu()) return cpu;
  const auto it = bound_.find(name);
  if (it != bound_.end()) return it->second;
  std::string list;
  for (const auto& [n, info] : bound_) list += (list.empty() ? "" : ", ") + n;
  throw Error("--backend vulkan: method '" + name + "' has no Vulkan implementation (" + list +
              " have one)");
}

std::vector<const MethodInfo*> ViewerMethods::listed() const {
  std::vector<const MethodInfo*> out;
  for (const MethodInfo& m : MethodRegistry::builtin().methods())
    if (!gpu() || bound_.count(m.name) > 0) out.push_back(gpu() ? &bound_.at(m.name) : &m);
  return out;
}

}  // namespace penumbra::viewer
