#include "penumbra/core/stats.hpp"

namespace penumbra {

void StageTimes::add(const std::string& stage, double ms) {
  for (auto& [name, value] : stages_) {
    if (name == stage) {
      value += ms;
      return;
    }
  }
  stages_.emplace_back(stage, ms);
}

double StageTimes::get(const std::string& stage) const {
  for (const auto& [name, value] : stages_)
    if (name == stage) return value;
  return 0.0;
}

double StageTimes::total() const {
  double sum = 0.0;
  for (const auto& entry : stages_) sum += entry.second;
  return sum;
}

void ScopedStage::stop() {
  if (!times_) return;
  times_->add(stage_, elapsed_ms(start_));
  times_ = nullptr;
}

double elapsed_ms(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

namespace {
// Set during static initialisation: every program that times anything links this file.
const std::chrono::steady_clock::time_point kProcessStart = std::chrono::steady_clock::now();
}  // namespace

std::chrono::steady_clock::time_point process_start() {
  return kProcessStart;
}

}  // namespace penumbra
