// Progress for long runs: a percentage line on stderr, shown only when stderr is a TTY.
#pragma once

#include <atomic>
#include <cstddef>
#include <string>

namespace penumbra {

class Progress {
 public:
  /// `label` names the work; `total` counts its units (rows, pixels, ...).
  Progress(std::string label, size_t total);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress();

  /// Thread-safe; redraws at most every 1 % of the work.
  void advance(size_t units = 1);
  static bool enabled();  // stderr is a terminal and PENUMBRA_NO_PROGRESS is unset

 private:
  std::string label_;
  size_t total_;
  std::atomic<size_t> done_{0};
  std::atomic<int> shown_percent_{-1};
  bool enabled_;
};

/// A per-method status line: on a terminal "  name ..." while it runs, completed in place
/// ("\r  name   12.3 ms"); in a log or a pipe only the completed line, plain and
/// newline-terminated (a "\r" there joins the two into one garbled line).
void begin_status_line(const std::string& running);
void end_status_line(const std::string& done);

/// Whether stderr holds an unterminated line (a progress percentage, a "method ..." status): an
/// error printed then must start a fresh line rather than be appended to it.
void set_stderr_line_open(bool open);
bool stderr_line_open();

}  // namespace penumbra
