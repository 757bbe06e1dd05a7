#include "penumbra/core/error.hpp"

#include <cstdio>

namespace penumbra {

namespace {

/// Appends `text` escaped, stopping before the escaped form exceeds `max_chars`; returns how many
/// input bytes were consumed.
size_t append_escaped(std::string& out, std::string_view text, size_t max_chars) {
  size_t used = 0;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    char piece[8];
    if (c == '\n') {
      std::snprintf(piece, sizeof piece, "\\n");
    } else if (c == '\r') {
      std::snprintf(piece, sizeof piece, "\\r");
    } else if (c == '\t') {
      std::snprintf(piece, sizeof piece, "\\t");
    } else if (c == '\\' || c == '\'') {
      std::snprintf(piece, sizeof piece, "\\%c", ch);
    } else if (c < 0x20 || c >= 0x7f) {
      std::snprintf(piece, sizeof piece, "\\x%02x", c);
    } else {
      piece[0] = ch;
      piece[1] = '\0';
    }
    const std::string_view p(piece);
    if (out.size() + p.size() > max_chars) break;
    out += p;
    ++used;
  }
  return used;
}

std::string escaped_and_cut(std::string_view text, size_t max_chars, bool escape_quotes) {
  std::string out;
  size_t used = 0;
  if (escape_quotes) {
    used = append_escaped(out, text, max_chars);
  } else {
    // Messages keep their own quotes and backslashes readable; only what breaks a line is escaped.
    for (const char ch : text) {
      const auto c = static_cast<unsigned char>(ch);
      if (c >= 0x20 && c < 0x7f && out.size() < max_chars) {
        out += ch;
      } else if (c < 0x20 || c >= 0x7f) {
        std::string piece;
        append_escaped(piece, std::string_view(&ch, 1), 8);
        if (out.size() + piece.size() > max_chars) break;
        out += piece;
      } else {
        break;
      }
      ++used;
    }
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
