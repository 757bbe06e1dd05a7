#include "penumbra/core/files.hpp"

#include <unistd.h>

#include <cerrno>
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
