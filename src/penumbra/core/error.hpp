// User-facing errors: bad input, bad options. The CLI prints what() on one line and exits 1.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace penumbra {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A user-supplied string (a key, a path, a name, a value) as it may appear in a one-line
/// message: in single quotes, control characters and non-ASCII bytes escaped (`\n`, `\x1b`), cut
/// to `max_chars` characters with the original length noted — a `\n` in a scene key cannot forge a
/// second line and a 3 MB string is not echoed whole.
std::string quote(std::string_view text, size_t max_chars = 80);

/// A whole message made safe for one terminal line: escaped like quote() (without the quotes)
/// and cut to `max_chars`. The CLI's last line of defence; messages should quote their parts.
std::string one_line(std::string_view message, size_t max_chars = 600);

}  // namespace penumbra
