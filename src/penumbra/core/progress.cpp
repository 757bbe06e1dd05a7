#include "penumbra/core/progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace penumbra {

namespace {
std::atomic<bool> g_stderr_line_open{false};
}  // namespace

void set_stderr_line_open(bool open) {
  g_stderr_line_open.store(open);
}
bool stderr_line_open() {
  return g_stderr_line_open.load();
}

void begin_status_line(const std::string& running) {
  if (!isatty(STDERR_FILENO)) return;
  std::fprintf(stderr, "%s ...", running.c_str());
  std::fflush(stderr);
  set_stderr_line_open(true);
}

void end_status_line(const std::string& done) {
  // On a terminal the running line is overwritten and cleared to its end.
  std::fprintf(stderr, "%s%s\n", stderr_line_open() ? "\r\033[K" : "", done.c_str());
  set_stderr_line_open(false);
}

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)), total_(total), enabled_(enabled() && total > 0) {}

Progress::~Progress() {
  if (enabled_ && shown_percent_.load() >= 0) {
    std::fprintf(stderr, "\r\033[K");  // the line is blank again, whatever preceded the bar
    set_stderr_line_open(false);
  }
}

bool Progress::enabled() {
  return isatty(STDERR_FILENO) && std::getenv("PENUMBRA_NO_PROGRESS") == nullptr;
}

void Progress::advance(size_t units) {
  const size_t done = done_.fetch_add(units) + units;
  if (!enabled_) return;
  const int percent = static_cast<int>(100 * done / total_);
  int shown = shown_percent_.load();
  while (percent > shown) {
    if (shown_percent_.compare_exchange_weak(shown, percent)) {
      std::fprintf(stderr, "\r%s %3d%%", label_.c_str(), percent);
      std::fflush(stderr);
      set_stderr_line_open(true);
      break;
    }
  }
}

}  // namespace penumbra
