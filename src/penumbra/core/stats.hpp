// Named stage times and method counters: what every method reports besides its image.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

/// Stage times in milliseconds, in the order the stages ran.
class StageTimes {
 public:
  void add(const std::string& stage, double ms);
  double get(const std::string& stage) const;  // 0 if absent
  double total() const;
  const std::vector<std::pair<std::string, double>>& stages() const { return stages_; }

 private:
  std::vector<std::pair<std::string, double>> stages_;
};

/// Method statistics (wedges, candidate pairs, ...). Doubles so averages fit too.
using Counters = std::map<std::string, double>;

/// Measures wall time from construction to stop() (or destruction) into a StageTimes entry.
class ScopedStage {
 public:
  ScopedStage(StageTimes& times, std::string stage)
      : times_(&times), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;
  ~ScopedStage() { stop(); }
  void stop();

 private:
  StageTimes* times_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
};

/// Milliseconds elapsed since `start`.
double elapsed_ms(std::chrono::steady_clock::time_point start);

/// The time of the program's static initialisation (after the dynamic loader, before main): the
/// start of a whole-process timing such as `render`'s stats.json "frame" block.
std::chrono::steady_clock::time_point process_start();

}  // namespace penumbra
