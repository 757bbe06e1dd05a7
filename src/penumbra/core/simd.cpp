#include "penumbra/core/simd.hpp"

#include <cstdlib>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "penumbra/core/simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace penumbra::simd::HWY_NAMESPACE {
// The target this copy was compiled for: dispatched like every kernel, so it names the one that
// runs.
int64_t compiled_target() {
  return HWY_TARGET;
}
}  // namespace penumbra::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "penumbra/core/error.hpp"

namespace penumbra::simd {

namespace {

HWY_EXPORT(compiled_target);

struct Named {
  const char* name;     // PENUMBRA_SIMD
  const char* display;  // stats.json, the report
  int64_t targets;      // Highway targets it stands for
  const char* embree;   // Embree's isa= value
};

constexpr Named kTargets[] = {
#if HWY_ARCH_X86
    {"avx512", "AVX-512", HWY_AVX3 | HWY_AVX3_DL, "avx512"},
    {"avx2", "AVX2", HWY_AVX2, "avx2"},
    {"sse4", "SSE4", HWY_SSE4 | HWY_SSSE3, "sse4.2"},
    {"scalar", "scalar", HWY_EMU128 | HWY_SCALAR, "sse2"},
#elif HWY_ARCH_ARM
    {"neon", "NEON", HWY_NEON, ""},
    {"scalar", "scalar", HWY_EMU128 | HWY_SCALAR, ""},
#else
    {"scalar", "scalar", HWY_EMU128 | HWY_SCALAR, ""},
#endif
};

const Named* pinned = nullptr;

int64_t usable() {
  return hwy::SupportedTargets() & HWY_TARGETS;
}

}  // namespace

std::vector<std::string> available() {
  std::vector<std::string> names;
  hwy::SetSupportedTargetsForTest(0);  // the CPU's own set, not a pin's
  const int64_t have = usable();
  if (pinned != nullptr) hwy::SetSupportedTargetsForTest(pinned->targets);
  for (const Named& t : kTargets)
    if ((have & t.targets) != 0) names.push_back(t.name);
  return names;
}

void pin(const std::string& name) {
  if (name.empty()) {
    pinned = nullptr;
    hwy::SetSupportedTargetsForTest(0);
    return;
  }
  const Named* found = nullptr;
  for (const Named& t : kTargets)
    if (name == t.name) found = &t;
  std::string names;
  for (const std::string& n : available()) names += (names.empty() ? "" : ", ") + n;
  if (found == nullptr)
    throw Error("PENUMBRA_SIMD=" + quote(name) + " is not a SIMD target (this CPU has: " + names +
                ")");
  hwy::SetSupportedTargetsForTest(0);
  if ((usable() & found->targets) == 0)
    throw Error("PENUMBRA_SIMD=" + quote(name) + ": this CPU or build lacks it (it has: " + names +
                ")");
  pinned = found;
  hwy::SetSupportedTargetsForTest(found->targets);
}

void configure_from_environment() {
  const char* env = std::getenv("PENUMBRA_SIMD");
  pin(env != nullptr ? env : "");
}

std::string active_target() {
  const int64_t t = HWY_DYNAMIC_DISPATCH(compiled_target)();
  for (const Named& n : kTargets)
    if ((n.targets & t) != 0) return n.display;
  return hwy::TargetName(t);
}

bool at_least_avx2() {
#if HWY_ARCH_X86
  return (HWY_DYNAMIC_DISPATCH(compiled_target)() & (HWY_AVX2 | HWY_AVX3 | HWY_AVX3_DL)) != 0;
#else
  return false;
#endif
}

std::string embree_isa() {
  return pinned != nullptr ? pinned->embree : "";
}

}  // namespace penumbra::simd
#endif  // HWY_ONCE
