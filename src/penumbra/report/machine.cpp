#include "penumbra/report/machine.hpp"

#include <ctime>
#include <fstream>
#include <thread>

#include "penumbra/core/simd.hpp"

namespace penumbra::report {

namespace {

std::string build_description() {
  std::string b = "C++ " + std::to_string(__cplusplus / 100) + ", ";
#if defined(__clang__)
  b += "clang " __clang_version__;
#elif defined(__GNUC__)
  b += "gcc " __VERSION__;
#endif
#if defined(__OPTIMIZE__)
  b += ", optimised";
#else
  b += ", not optimised";
#endif
#if defined(NDEBUG)
  b += ", NDEBUG";
#endif
#if defined(__SANITIZE_ADDRESS__)
  b += ", ASan+UBSan (times are not representative)";
#endif
  // The SIMD target the dispatched kernels ran on (PENUMBRA_SIMD or the CPU's best).
  b += ", SIMD " + simd::active_target();
#if defined(__AVX512F__)
  b += ", compiled for AVX-512";
#elif defined(__AVX2__)
  b += ", compiled for AVX2";
#endif
  return b;
}

}  // namespace

MachineInfo machine_info() {
  MachineInfo m;
  m.cores = std::thread::hardware_concurrency();
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) m.cpu = line.substr(line.find_first_not_of(' ', colon + 1));
      break;
    }
  }
  if (m.cpu.empty()) m.cpu = "unknown CPU";
  std::ifstream loadavg("/proc/loadavg");
  std::string a, b, c;
  if (loadavg >> a >> b >> c) m.load = a + " " + b + " " + c;
  m.build = build_description();
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", &tm);
  m.date_utc = date;
  return m;
}

}  // namespace penumbra::report
