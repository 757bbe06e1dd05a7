// Reading and writing files safely: inputs must be regular files (a FIFO or /dev/zero would be read
// forever), outputs appear under their final name only when completely written.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace penumbra {

/// "" when `path` names an existing regular file (symbolic links followed), else why not: "no such
/// file", "is a directory", "not a regular file (...)".
std::string regular_file_problem(const std::filesystem::path& path);

/// Throws Error("<what> '<path>': <problem>") unless `path` names an existing regular file.
void require_regular_file(const std::filesystem::path& path, std::string_view what);

/// Writes `path` atomically: `write` is called with a temporary name in the same folder, whose
/// contents are then renamed over `path`. If `write` throws, or the file cannot be flushed or
/// renamed, the temporary is removed and Error is thrown — a full disk or an unwritable folder
/// never leaves a half-written file under the final name.
void write_file_atomically(
    const std::filesystem::path& path,
    const std::function<void(const std::filesystem::path& temporary)>& write);

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporaries write_file_atomically is writing
/// (hidden ".NAME.partial-PID" files, up to the size of the output) before the process dies of
/// the signal, as it would have without the handler. Signals the process ignores stay ignored.
/// For programs (the CLI), not libraries: it replaces the handlers of those signals.
void remove_temporaries_on_signal();

/// write_file_atomically for text or bytes, every write checked.
void write_text_file(const std::filesystem::path& path, std::string_view text);

}  // namespace penumbra
