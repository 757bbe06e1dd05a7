// Where and how a measurement ran, for report headers: CPU, cores, load, build, date.
#pragma once

#include <string>

namespace penumbra::report {

struct MachineInfo {
  std::string cpu;       // /proc/cpuinfo model name
  unsigned cores = 0;    // hardware threads
  std::string load;      // /proc/loadavg 1/5/15-minute averages
  std::string build;     // compiler, optimisation, sanitizers, SIMD target
  std::string date_utc;  // ISO 8601
};

MachineInfo machine_info();

}  // namespace penumbra::report
