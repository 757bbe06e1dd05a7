#include "penumbra/scene/off_reader.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

namespace penumbra {

namespace {

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
bool is_blank(char c) {
  return c == ' ' || c == '\t';
}

/// One line of the body, without its '\n' and a trailing '\r'; false at the end of the data.
bool next_line(std::string_view bytes, size_t& pos, std::string_view& line) {
  if (pos >= bytes.size()) return false;
  const size_t end = bytes.find('\n', pos);
  const size_t stop = end == std::string_view::npos ? bytes.size() : end;
  line = bytes.substr(pos, stop - pos);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos = end == std::string_view::npos ? bytes.size() : end + 1;
  return true;
}

/// Reads the decimal digits at `c` (at most `max_digits`; further digits are skipped), as
/// assimp's strtoul10_64 does; `digits` is how many were read. False when there is no digit or
/// the value could overflow.
bool read_digits(std::string_view s, size_t& c, int max_digits, uint64_t& value, int& digits) {
  value = 0;
  digits = 0;
  if (c >= s.size() || !is_digit(s[c])) return false;
  while (c < s.size() && is_digit(s[c])) {
    if (digits < max_digits) {
      value = value * 10 + static_cast<uint64_t>(s[c] - '0');
      ++digits;
    }
    ++c;
  }
  return true;
}

/// 10^-k as assimp's table holds it (double literals).
constexpr double kNegativePowers[16] = {0.0,  0.1,  0.01,  0.001, 1e-4,  1e-5,  1e-6,  1e-7,
                                        1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15};

/// A number "[+-]digits[.digits][e[+-]digits]" or "[+-].digits[...]", as assimp's
/// fast_atoreal_move<float> reads it: the integer part converted to float, the fraction's first 15
/// digits times 10^-count in double, converted to float and added, the sum times powf(10,
/// exponent). False for any other token (inf, nan, hexadecimal, ...).
bool read_coordinate(std::string_view s, size_t& c, float& out) {
  const bool negative = c < s.size() && s[c] == '-';
  if (c < s.size() && (s[c] == '-' || s[c] == '+')) ++c;
  float value = 0.0f;
  uint64_t digits_value = 0;
  int digits = 0;
  bool any = false;
  if (c < s.size() && s[c] != '.') {
    // 19 digits always fit in 64 bits; more would make assimp's reader overflow.
    if (!read_digits(s, c, 19, digits_value, digits) || digits == 19) return false;
    value = static_cast<float>(digits_value);
    any = true;
  }
  if (c + 1 < s.size() && s[c] == '.' && is_digit(s[c + 1])) {
    ++c;
    read_digits(s, c, 15, digits_value, digits);
    value += static_cast<float>(static_cast<double>(digits_value) * kNegativePowers[digits]);
    any = true;
  } else if (c < s.size() && s[c] == '.') {
    ++c;  // a trailing dot
  }
  if (!any) return false;
  if (c < s.size() && (s[c] == 'e' || s[c] == 'E')) {
    // The exponent: value × powf(10, ±digits), in float.
    ++c;
    const bool negative_exponent = c < s.size() && s[c] == '-';
    if (c < s.size() && (s[c] == '-' || s[c] == '+')) ++c;
    // Beyond 10^±30 the validation's double reading could overflow or underflow where powf
    // gives inf or 0: such files keep its verdict.
    if (!read_digits(s, c, 19, digits_value, digits) || digits_value > 30) return false;
    const float exponent = static_cast<float>(digits_value);
    value *= std::pow(10.0f, negative_exponent ? -exponent : exponent);
  }
  if (c < s.size() && !is_blank(s[c])) return false;
  out = negative ? -value : value;
  return true;
}

bool read_index(std::string_view s, size_t& c, uint64_t& out) {
  int digits = 0;
  return read_digits(s, c, 19, out, digits) && digits < 10 && (c == s.size() || is_blank(s[c]));
}

void skip_blanks(std::string_view s, size_t& c) {
  while (c < s.size() && is_blank(s[c])) ++c;
}

/// The header: "OFF" alone on the first line, "vertices faces edges" alone on the next.
bool read_header(std::string_view bytes, size_t& pos, uint64_t& nv, uint64_t& nf) {
  std::string_view line;
  if (!next_line(bytes, pos, line) || line != "OFF") return false;
  if (!next_line(bytes, pos, line)) return false;
  size_t c = 0;
  uint64_t edges = 0;
  skip_blanks(line, c);
  if (!read_index(line, c, nv)) return false;
  skip_blanks(line, c);
  if (!read_index(line, c, nf)) return false;
  skip_blanks(line, c);
  if (!read_index(line, c, edges)) return false;
  skip_blanks(line, c);
  return c == line.size() && nv > 0 && nf > 0;
}

/// The next line with something on it; empty lines are skipped as assimp skips them. A line of
/// blanks only or a comment is outside the subset (assimp reads those differently).
bool next_body_line(std::string_view bytes, size_t& pos, std::string_view& line) {
  while (next_line(bytes, pos, line)) {
    if (line.empty()) continue;
    for (char ch : line)
      if (ch == '#' || ch == '\f' || ch == '\0' || ch == '\r') return false;
    // assimp copies a line into a 4096-byte buffer: longer ones are outside the subset.
    return line.size() < 4000;
  }
  return false;
}

/// The next line with tokens left once a '#' comment is cut, split at blanks (as the validation
/// splits it); false at the end of the data.
bool next_tokens(std::string_view bytes, size_t& pos, std::vector<std::string_view>& tokens) {
  const auto is_space = [](char ch) {
    return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\f' || ch == '\v';
  };
  std::string_view line;
  while (next_line(bytes, pos, line)) {
    if (const size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    tokens.clear();
    for (size_t i = 0; i < line.size();) {
      while (i < line.size() && is_space(line[i])) ++i;
      const size_t start = i;
      while (i < line.size() && !is_space(line[i])) ++i;
      if (i > start) tokens.push_back(line.substr(start, i - start));
    }
    if (!tokens.empty()) return true;
  }
  return false;
}

uint64_t to_count(std::string_view token) {
  uint64_t value = 0;
  for (char ch : token) value = value * 10 + static_cast<uint64_t>(ch - '0');
  return value;
}

/// assimp's OFF importer reads faces of 1 to 9 indices.
constexpr uint64_t kAssimpOffMaxFaceIndices = 9;

}  // namespace

std::optional<std::string> off_polygons_as_obj(std::string_view bytes) {
  // The header as validate_off reads it: [ST][C][N][4][n]OFF, an optional dimension, the counts.
  size_t pos = 0;
  std::vector<std::string_view> t;
  if (!next_tokens(bytes, pos, t)) return std::nullopt;
  const std::string_view keyword = t[0];
  std::vector<std::string_view> rest(t.begin() + 1, t.end());
  if (keyword.find("nOFF") != std::string_view::npos) {
    if (rest.empty() && !next_tokens(bytes, pos, rest)) return std::nullopt;
    rest.erase(rest.begin());
  }
  if (rest.empty() && !next_tokens(bytes, pos, rest)) return std::nullopt;
  if (rest.size() < 2) return std::nullopt;
  const uint64_t nv = to_count(rest[0]), nf = to_count(rest[1]);

  const size_t body = pos;  // first pass: is there a face assimp's OFF importer would drop?
  for (uint64_t v = 0; v < nv; ++v)
    if (!next_tokens(bytes, pos, t)) return std::nullopt;
  bool long_face = false;
  for (uint64_t f = 0; f < nf && !long_face; ++f) {
    if (!next_tokens(bytes, pos, t)) return std::nullopt;
    long_face = to_count(t[0]) > kAssimpOffMaxFaceIndices;
  }
  if (!long_face) return std::nullopt;

  std::string obj;
  obj.reserve(bytes.size() + 4 * (nv + nf));
  pos = body;
  for (uint64_t v = 0; v < nv; ++v) {
    next_tokens(bytes, pos, t);
    obj.append("v ").append(t[0]).append(" ").append(t[1]).append(" ").append(t[2]).append("\n");
  }
  for (uint64_t f = 0; f < nf; ++f) {
    next_tokens(bytes, pos, t);
    const uint64_t n = to_count(t[0]);
    if (n < 3) continue;  // points and lines: dropped by the import either way
    obj.append("f");
    for (uint64_t k = 1; k <= n; ++k)  // OBJ counts vertices from 1
      obj.append(" ").append(std::to_string(to_count(t[k]) + 1));
    obj.append("\n");
  }
  return obj;
}

std::optional<Mesh> read_plain_off(std::string_view bytes, const std::string& name) {
  size_t pos = 0;
  uint64_t nv = 0, nf = 0;
  if (!read_header(bytes, pos, nv, nf)) return std::nullopt;
  // A vertex line takes at least 6 bytes ("0 0 0\n"), a face line 8: a larger count is a lying
  // header, left to the validation's message before anything is allocated.
  if (nv > (bytes.size() - pos) / 6 || nf > (bytes.size() - pos) / 8) return std::nullopt;

  std::vector<Vec3> file_positions(nv);
  std::string_view line;
  for (uint64_t v = 0; v < nv; ++v) {
    if (!next_body_line(bytes, pos, line)) return std::nullopt;
    size_t c = 0;
    for (int k = 0; k < 3; ++k) {
      skip_blanks(line, c);
      float x = 0.0f;
      if (!read_coordinate(line, c, x)) return std::nullopt;
      if (x != 0.0f && !(std::abs(x) >= 1e-12f)) return std::nullopt;  // also NaN
      if (!std::isfinite(x)) return std::nullopt;
      file_positions[v][k] = x;
    }
    skip_blanks(line, c);
    if (c != line.size()) return std::nullopt;  // colours or a 4th coordinate
  }

  Mesh mesh;
  mesh.name = name;
  mesh.triangles.reserve(nf);
  for (uint64_t f = 0; f < nf; ++f) {
    if (!next_body_line(bytes, pos, line)) return std::nullopt;
    size_t c = 0;
    uint64_t count = 0, index[3] = {0, 0, 0};
    skip_blanks(line, c);
    if (!read_index(line, c, count) || count != 3) return std::nullopt;
    for (uint64_t& i : index) {
      skip_blanks(line, c);
      if (!read_index(line, c, i) || i >= nv) return std::nullopt;
    }
    skip_blanks(line, c);
    if (c != line.size()) return std::nullopt;
    mesh.triangles.push_back(
        Triangle{{static_cast<uint32_t>(index[0]), static_cast<uint32_t>(index[1]),
                  static_cast<uint32_t>(index[2])}});
  }

  // aiProcess_JoinIdenticalVertices: the vertices faces use, in file order, each joined into the
  // first one at an equal position (+0 and −0 are equal).
  std::vector<bool> used(nv, false);
  for (const Triangle& t : mesh.triangles)
    for (uint32_t i : t.v) used[i] = true;
  const auto key = [](const Vec3& q) {  // q without −0: equal floats give equal keys
    uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      uint32_t bits = 0;
      std::memcpy(&bits, &q[k], 4);
      h = (h ^ bits) * 1099511628211ull;
    }
    return h;
  };
  std::unordered_multimap<uint64_t, uint32_t> first_at;
  first_at.reserve(nv);
  std::vector<uint32_t> renumbered(nv, 0);
  mesh.positions.reserve(nv);
  for (uint64_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    // The importer's identity node transform adds 0: −0 → +0.
    const Vec3 q = file_positions[v] + Vec3(0.0f);
    const uint64_t h = key(q);
    uint32_t joined = std::numeric_limits<uint32_t>::max();
    for (auto [it, last] = first_at.equal_range(h); it != last; ++it)
      if (const Vec3& r = mesh.positions[it->second]; r.x == q.x && r.y == q.y && r.z == q.z) {
        joined = it->second;
        break;
      }
    if (joined == std::numeric_limits<uint32_t>::max()) {
      joined = static_cast<uint32_t>(mesh.positions.size());
      mesh.positions.push_back(q);
      first_at.emplace(h, joined);
    }
    renumbered[v] = joined;
  }
  for (Triangle& t : mesh.triangles)
    for (uint32_t& i : t.v) i = renumbered[i];
  return mesh;
}

}  // namespace penumbra
