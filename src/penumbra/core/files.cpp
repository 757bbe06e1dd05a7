#include "penumbra/core/files.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include "penumbra/core/error.hpp"

namespace penumbra {

namespace fs = std::filesystem;

std::string regular_file_problem(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) return "no such file";
  if (fs::is_directory(status)) return "is a directory";
  if (!fs::is_regular_file(status))
    return "not a regular file (a FIFO, socket or device cannot be read as one)";
  return "";
}

void require_regular_file(const fs::path& path, std::string_view what) {
  const std::string problem = regular_file_problem(path);
  if (!problem.empty())
    throw Error(std::string(what) + " " + quote(path.string(), 200) + ": " + problem);
}

namespace {

// The temporaries being written, for the signal handler: fixed slots (a handler may not
// allocate or lock), each claimed with a compare-and-swap. A slot's path is complete before its
// state says so; the handler reads only complete slots.
constexpr size_t kTemporarySlots = 64;
constexpr size_t kTemporaryPathBytes = 4096;
enum SlotState : int { kFree = 0, kFilling = 1, kActive = 2 };
struct TemporarySlot {
  std::atomic<int> state{kFree};
  char path[kTemporaryPathBytes] = {};
};
std::array<TemporarySlot, kTemporarySlots> g_temporaries;
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots");

/// Registers a temporary for the lifetime of the object (no slot free, or a path too long: not
/// registered, the file is then only removed by the normal paths).
class TemporaryRegistration {
 public:
  explicit TemporaryRegistration(const fs::path& path) {
    const std::string& text = path.native();
    if (text.size() >= kTemporaryPathBytes) return;
    for (TemporarySlot& slot : g_temporaries) {
      int expected = kFree;
      if (!slot.state.compare_exchange_strong(expected, kFilling)) continue;
      std::memcpy(slot.path, text.c_str(), text.size() + 1);
      slot.state.store(kActive);
      slot_ = &slot;
      return;
    }
  }
  ~TemporaryRegistration() {
    if (slot_) slot_->state.store(kFree);
  }
  TemporaryRegistration(const TemporaryRegistration&) = delete;
  TemporaryRegistration& operator=(const TemporaryRegistration&) = delete;

 private:
  TemporarySlot* slot_ = nullptr;
};

/// Only async-signal-safe calls: unlink, signal, raise.
extern "C" void remove_temporaries_and_reraise(int signal_number) {
  const int saved_errno = errno;
  for (TemporarySlot& slot : g_temporaries)
    if (slot.state.load() == kActive) ::unlink(slot.path);
  errno = saved_errno;
  // The default action now (terminate), so the parent sees the process killed by this signal.
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

}  // namespace

void remove_temporaries_on_signal() {
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction previous {};
    if (::sigaction(signal_number, nullptr, &previous) != 0) continue;
    // A signal the caller ignores (nohup, a background job's SIGINT) stays ignored.
    if (previous.sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    ::sigaction(signal_number, &action, nullptr);
  }
}

void write_file_atomically(const fs::path& path,
                           const std::function<void(const fs::path& temporary)>& write) {
  const std::string who = "cannot write " + quote(path.string(), 200);
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(who + ": a directory has that name");
  // Same folder, so the rename is atomic (same file system); hidden, and unique per process.
  std::string name(1, '.');  // (built by appends: GCC 12 misreports "." + string as overlapping)
  name += path.filename().string();
  name += ".partial-";
  name += std::to_string(::getpid());
  const fs::path temporary = path.parent_path() / name;
  const TemporaryRegistration registration(temporary);
  try {
    write(temporary);
  } catch (const Error&) {
    fs::remove(temporary, ec);
    throw;
  } catch (const std::exception& e) {
    fs::remove(temporary, ec);
    throw Error(who + ": " + e.what());
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw Error(who + ": " + ec.message());
  }
}

void write_text_file(const fs::path& path, std::string_view text) {
  write_file_atomically(path, [&](const fs::path& temporary) {
    const std::string who = "cannot write " + quote(path.string(), 200);
    std::FILE* f = std::fopen(temporary.c_str(), "wb");
    if (!f) throw Error(who + ": " + std::strerror(errno));
    const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    const int write_errno = errno;
    // Buffered data reaches the file system here: a full disk fails now, before the rename.
    const bool flushed = std::fflush(f) == 0;
    const int flush_errno = errno;
    const bool closed = std::fclose(f) == 0;
    if (!written) throw Error(who + ": " + std::strerror(write_errno));
    if (!flushed || !closed) throw Error(who + ": " + std::strerror(flush_errno));
  });
}

}  // namespace penumbra
