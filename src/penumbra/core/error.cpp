#include "penumbra/core/error.hpp"

#include <cstdio>

namespace penumbra {

namespace {

/// A byte that could break the line or drive the terminal: C0 controls and DEL. Bytes ≥ 0x80 pass
/// (UTF-8 names and paths stay readable) except the UTF-8 form of the C1 controls, see is_c1.
bool is_control(unsigned char c) {
  return c < 0x20 || c == 0x7f;
}

/// UTF-8 C1 control (U+0080..U+009F: 0xC2 0x80..0x9F), which some terminals obey like ESC.
bool is_c1(std::string_view text, size_t i) {
  return static_cast<unsigned char>(text[i]) == 0xc2 && i + 1 < text.size() &&
         static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
         static_cast<unsigned char>(text[i + 1]) <= 0x9f;
}

std::string escape_byte(unsigned char c) {
  switch (c) {
    case '\n':
      return "\\n";
    case '\r':
      return "\\r";
    case '\t':
      return "\\t";
    default: {
      char piece[8];
      std::snprintf(piece, sizeof piece, "\\x%02x", c);
      return piece;
    }
  }
}

/// `text` with control characters escaped (and, in a quoted string, the quote and backslash),
/// cut so that it stays within `max_chars`; a cut notes the original length.
std::string escaped_and_cut(std::string_view text, size_t max_chars, bool escape_quotes) {
  std::string out;
  size_t used = 0;
  for (; used < text.size(); ++used) {
    const auto c = static_cast<unsigned char>(text[used]);
    std::string piece;
    if (is_control(c)) {
      piece = escape_byte(c);
    } else if (is_c1(text, used)) {
      piece = escape_byte(c) + escape_byte(static_cast<unsigned char>(text[used + 1]));
    } else if (escape_quotes && (c == '\\' || c == '\'')) {
      piece = {'\\', static_cast<char>(c)};
    } else {
      piece = std::string(1, static_cast<char>(c));
    }
    if (out.size() + piece.size() > max_chars) break;
    out += piece;
    if (is_c1(text, used)) ++used;
  }
  if (used < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace

std::string quote(std::string_view text, size_t max_chars) {
  std::string out(1, '\'');
  out += escaped_and_cut(text, max_chars, true);
  out += '\'';
  return out;
}

std::string one_line(std::string_view message, size_t max_chars) {
  return escaped_and_cut(message, max_chars, false);
}

}  // namespace penumbra
