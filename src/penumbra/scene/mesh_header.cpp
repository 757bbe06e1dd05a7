#include "penumbra/scene/mesh_header.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

#include "penumbra/core/error.hpp"

namespace penumbra {

namespace {

[[noreturn]] void bad(const std::string& what) {
  throw Error(what);
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

/// Whitespace-separated tokens of one line, into `out` (cleared first). The caller keeps `out`
/// across lines: a fresh vector per line made the allocator a third of the validation's time on a
/// 2.6 MB OFF file.
void split(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

bool parse_uint(std::string_view token, uint64_t& value) {
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value, 10);
  return ec == std::errc{} && end == token.data() + token.size();
}

bool parse_int(std::string_view token, int64_t& value) {
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value, 10);
  return ec == std::errc{} && end == token.data() + token.size();
}

bool parse_number(std::string_view token, double* out = nullptr) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (out) *out = value;
  return ec == std::errc{} && end == token.data() + token.size();
}

/// A vertex coordinate: a number that is finite in float. Checked here because assimp's
/// JoinIdenticalVertices would merge a NaN vertex into another before the loader could see it.
bool parse_coordinate(std::string_view token) {
  double value = 0.0;
  return parse_number(token, &value) && std::isfinite(value) &&
         std::abs(value) <= std::numeric_limits<float>::max();
}

/// Reads lines of `bytes` from `pos`; returns false at the end of the data.
bool next_line(std::string_view bytes, size_t& pos, std::string_view& line) {
  if (pos >= bytes.size()) return false;
  const size_t end = bytes.find('\n', pos);
  const size_t stop = end == std::string_view::npos ? bytes.size() : end;
  line = bytes.substr(pos, stop - pos);
  pos = end == std::string_view::npos ? bytes.size() : end + 1;
  return true;
}

void add_face(MeshFileCounts& counts, uint64_t n) {
  ++counts.faces;
  if (n >= 3) counts.triangles += n - 2;
}

// ---- PLY -------------------------------------------------------------------------------------

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

bool ply_type(std::string_view name, PlyType& t) {
  static const std::pair<const char*, PlyType> kTypes[] = {
      {"char", PlyType::int8},      {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
      {"uint8", PlyType::uint8},    {"short", PlyType::int16},     {"int16", PlyType::int16},
      {"ushort", PlyType::uint16},  {"uint16", PlyType::uint16},   {"int", PlyType::int32},
      {"int32", PlyType::int32},    {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
      {"float", PlyType::float32},  {"float32", PlyType::float32}, {"double", PlyType::float64},
      {"float64", PlyType::float64}};
  for (const auto& [n, type] : kTypes)
    if (name == n) {
      t = type;
      return true;
    }
  return false;
}

size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::int8:
    case PlyType::uint8:
      return 1;
    case PlyType::int16:
    case PlyType::uint16:
      return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32:
      return 4;
    case PlyType::float64:
      return 8;
  }
  return 1;
}

bool ply_is_integer(PlyType t) {
  return t != PlyType::float32 && t != PlyType::float64;
}

struct PlyProperty {
  bool list = false;
  PlyType count_type = PlyType::uint8;
  PlyType type = PlyType::float32;
  std::string name;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { ascii, little_endian, big_endian };

/// Reads the body of a PLY file, element by element, checking every record.
class PlyBody {
 public:
  PlyBody(std::string_view body, PlyFormat format) : body_(body), format_(format) {}

  /// One integer (list counts, indices), from a binary value or an ASCII token.
  int64_t integer(PlyType t, const char* what) {
    if (format_ == PlyFormat::ascii) {
      int64_t v = 0;
      if (!parse_int(token(what), v)) bad(std::string("PLY: ") + what + " is not an integer");
      return v;
    }
    if (!ply_is_integer(t)) bad(std::string("PLY: ") + what + " has a floating-point type");
    const size_t n = ply_size(t);
    const unsigned char* p = take(n, what);
    uint64_t u = 0;
    for (size_t k = 0; k < n; ++k) {
      const size_t byte = format_ == PlyFormat::big_endian ? k : n - 1 - k;
      u = (u << 8) | p[byte];
    }
    switch (t) {
      case PlyType::int8:
        return static_cast<int8_t>(u);
      case PlyType::int16:
        return static_cast<int16_t>(u);
      case PlyType::int32:
        return static_cast<int32_t>(u);
      default:
        return static_cast<int64_t>(u);
    }
  }

  /// ASCII: a record is one line (as assimp reads it); starts the next non-blank one and returns
  /// false at the end of the data. Binary: always true (the reads check the length).
  bool begin_record() {
    if (format_ != PlyFormat::ascii) return true;
    // Past the previous record's line, also when it was the last one: a record that reads no
    // value must not start on the same line again (a header with a huge count of empty
    // records would loop on it).
    if (in_record_) pos_ = line_end_;
    in_record_ = true;
    while (pos_ < body_.size() && is_space(body_[pos_])) ++pos_;
    if (pos_ >= body_.size()) return false;
    const size_t end = body_.find('\n', pos_);
    line_end_ = end == std::string_view::npos ? body_.size() : end;
    return true;
  }
  /// ASCII: whether the current record has another value (assimp tolerates short records).
  bool has_value() {
    if (format_ != PlyFormat::ascii) return true;
    while (pos_ < line_end_ && is_space(body_[pos_])) ++pos_;
    return pos_ < line_end_;
  }

  /// Skips one value of any type (checking an ASCII token is a number); false when `coordinate`
  /// and the value is not finite in float.
  bool skip(PlyType t, const char* what, bool coordinate = false) {
    if (format_ == PlyFormat::ascii) {
      const std::string_view s = token(what);
      if (!parse_number(s)) bad(std::string("PLY: ") + what + " is not a number");
      return !coordinate || parse_coordinate(s);
    }
    const unsigned char* p = take(ply_size(t), what);
    if (!coordinate || (t != PlyType::float32 && t != PlyType::float64)) return true;
    const size_t n = ply_size(t);
    unsigned char b[8];
    for (size_t k = 0; k < n; ++k) b[k] = p[format_ == PlyFormat::big_endian ? n - 1 - k : k];
    double value = 0.0;
    if (t == PlyType::float32) {
      float f = 0.0f;
      std::memcpy(&f, b, 4);
      value = f;
    } else {
      std::memcpy(&value, b, 8);
    }
    return std::isfinite(value) && std::abs(value) <= std::numeric_limits<float>::max();
  }

 private:
  std::string_view token(const char* what) {
    while (pos_ < line_end_ && is_space(body_[pos_])) ++pos_;
    const size_t start = pos_;
    while (pos_ < line_end_ && !is_space(body_[pos_])) ++pos_;
    if (pos_ == start) bad(std::string("PLY: a record ends inside ") + what);
    return body_.substr(start, pos_ - start);
  }
  const unsigned char* take(size_t n, const char* what) {
    if (body_.size() - pos_ < n) bad(std::string("PLY: the file ends inside ") + what);
    const auto* p = reinterpret_cast<const unsigned char*>(body_.data() + pos_);
    pos_ += n;
    return p;
  }

  std::string_view body_;
  PlyFormat format_;
  size_t pos_ = 0;
  size_t line_end_ = 0;     // ASCII: end of the current record's line
  bool in_record_ = false;  // ASCII: a record has begun (line_end_ is its line's end)
};

MeshFileCounts validate_ply(std::string_view bytes) {
  size_t pos = 0;
  std::string_view line;
  next_line(bytes, pos, line);  // "ply"
  bool have_format = false;
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  std::vector<std::string_view> t;
  // The header's end first: without one, the lines below would be a binary body's bytes.
  bool have_end = false;
  for (size_t at = pos; !have_end && next_line(bytes, at, line);) {
    split(line, t);
    have_end = !t.empty() && t[0] == "end_header";
  }
  if (!have_end) bad("PLY header has no end_header line");
  while (next_line(bytes, pos, line)) {
    // Assimp does not split the header where this does: a control character other than a tab
    // reads differently there, in any line. A vertical tab after "end_header" hid its end (assimp
    // looped for ever); a NUL ended a stray line early, and the "element face 4000000000" after it
    // in the same line, which this would skip as stray text, made assimp allocate 64 GB (both
    // from a fuzzer).
    for (const char c : line)
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r')
        bad("PLY header: control character " + std::to_string(static_cast<int>(c)) + " in line " +
            quote(line));
    split(line, t);
    if (t.empty()) continue;
    if (t[0] == "end_header") break;
    if (t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (t.size() != 3 || t[2] != "1.0") bad("PLY header: malformed format line");
      if (t[1] == "ascii")
        format = PlyFormat::ascii;
      else if (t[1] == "binary_little_endian")
        format = PlyFormat::little_endian;
      else if (t[1] == "binary_big_endian")
        format = PlyFormat::big_endian;
      else
        bad("PLY header: unknown format " + quote(t[1]));
      have_format = true;
    } else if (t[0] == "element") {
      PlyElement e;
      if (t.size() != 3 || !parse_uint(t[2], e.count))
        bad("PLY header: malformed element line " + quote(line));
      e.name = t[1];
      // Assimp sizes its arrays from an element's first declaration and writes a second one's
      // records past them (a fuzzer's heap overflow, seen by valgrind).
      for (const PlyElement& other : elements)
        if (other.name == e.name) bad("PLY header: element " + quote(e.name) + " declared twice");
      elements.push_back(std::move(e));
    } else if (t[0] == "property") {
      if (elements.empty()) bad("PLY header: property before any element");
      PlyProperty p;
      if (t.size() == 5 && t[1] == "list") {
        p.list = true;
        if (!ply_type(t[2], p.count_type) || !ply_type(t[3], p.type) ||
            !ply_is_integer(p.count_type))
          bad("PLY header: malformed list property " + quote(line));
        p.name = t[4];
      } else if (t.size() == 3 && ply_type(t[1], p.type)) {
        p.name = t[2];
      } else {
        bad("PLY header: malformed property " + quote(line));
      }
      for (const PlyProperty& other : elements.back().properties)
        if (other.name == p.name)
          bad("PLY header: property " + quote(p.name) + " of " + quote(elements.back().name) +
              " declared twice");
      elements.back().properties.push_back(std::move(p));
    }
    // Other lines (an exporter's stray text) are skipped, as assimp skips them.
  }
  if (!have_format) bad("PLY header has no format line");

  const std::string_view body = bytes.substr(pos);
  // Assimp skips a line feed right after end_header even in a binary body, then reads every
  // record a byte off: garbage positions (a first x of 0.02f begins with that byte).
  if (format != PlyFormat::ascii && !body.empty() && body[0] == '\n')
    bad("binary PLY body starts with a line-feed byte, which assimp skips (every record would be "
        "read a byte off)");
  MeshFileCounts counts;
  const PlyElement* vertex = nullptr;
  for (const PlyElement& e : elements) {
    // Every record takes at least one byte per property (binary) or two (a digit and a
    // separator, ASCII): a larger count is a lying header, refused before anything is allocated.
    // An ASCII record is at least one non-blank line even without properties.
    // A binary record without properties is zero bytes, so nothing bounds its count: assimp
    // looped over a fuzzer's 4 000 000 000 of them.
    if (format != PlyFormat::ascii && e.properties.empty() && e.count > 0)
      bad("PLY header: element " + quote(e.name) + " has " + std::to_string(e.count) +
          " records but no properties");
    size_t min_bytes = format == PlyFormat::ascii && e.properties.empty() ? 1 : 0;
    for (const PlyProperty& p : e.properties)
      min_bytes += format == PlyFormat::ascii ? 2 : ply_size(p.list ? p.count_type : p.type);
    if (min_bytes > 0 && e.count > (body.size() + 1) / min_bytes)
      bad("corrupt header: PLY declares " + std::to_string(e.count) + " " + quote(e.name) +
          " elements, more than the file's " + std::to_string(body.size()) + " bytes can hold");
    if (e.name == "vertex") {
      vertex = &e;
      counts.vertices = e.count;
    }
  }

  PlyBody reader(body, format);
  for (const PlyElement& e : elements) {
    if (e.properties.empty() && format != PlyFormat::ascii) continue;  // no records (above)
    const bool is_face = e.name == "face";
    for (uint64_t r = 0; r < e.count; ++r) {
      if (!reader.begin_record())
        bad("PLY: the file ends after " + std::to_string(r) + " of " + std::to_string(e.count) +
            " " + quote(e.name) + " elements");
      for (const PlyProperty& p : e.properties) {
        const bool indices = is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (!indices && !reader.has_value()) break;  // a short ASCII record, as assimp allows
        if (!p.list) {
          const bool coordinate = &e == vertex && (p.name == "x" || p.name == "y" || p.name == "z");
          if (!reader.skip(p.type, e.name.c_str(), coordinate))
            bad("PLY: vertex " + std::to_string(r) + " has a NaN or infinite coordinate");
          continue;
        }
        const int64_t n = reader.integer(p.count_type, "a list count");
        if (n < 0) bad("PLY: negative list count in " + quote(e.name) + " " + std::to_string(r));
        if (indices && n == 0) bad("PLY: face " + std::to_string(r) + " has no vertex indices");
        for (int64_t k = 0; k < n; ++k) {
          if (!indices) {
            reader.skip(p.type, e.name.c_str());
            continue;
          }
          const int64_t index = reader.integer(p.type, "a vertex index");
          if (!vertex || index < 0 || static_cast<uint64_t>(index) >= vertex->count)
            bad("PLY: face " + std::to_string(r) + " has vertex index " + std::to_string(index) +
                " (the file has " + std::to_string(counts.vertices) + " vertices)");
        }
        if (indices) add_face(counts, static_cast<uint64_t>(n));
      }
    }
  }
  return counts;
}

// ---- OFF -------------------------------------------------------------------------------------

/// The next line with something left after removing a '#' comment; false at the end.
bool next_content_line(std::string_view bytes, size_t& pos, std::vector<std::string_view>& tokens) {
  std::string_view line;
  while (next_line(bytes, pos, line)) {
    if (const size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    split(line, tokens);
    if (!tokens.empty()) return true;
  }
  return false;
}

MeshFileCounts validate_off(std::string_view bytes) {
  size_t pos = 0;
  std::vector<std::string_view> t;
  if (!next_content_line(bytes, pos, t)) bad("OFF: empty file");
  // [ST][C][N][4][n]OFF: the keyword, possibly followed by the counts on the same line.
  const std::string_view keyword = t[0];
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
    bad("OFF: the file does not start with an OFF keyword");
  std::vector<std::string_view> rest(t.begin() + 1, t.end());
  if (!rest.empty() && rest[0] == "BINARY") bad("OFF: binary OFF files are not supported");
  size_t dimension = keyword.find('4') != std::string_view::npos ? 4 : 3;
  if (keyword.find("nOFF") != std::string_view::npos) {
    if (rest.empty() && !next_content_line(bytes, pos, rest)) bad("OFF: missing dimension");
    uint64_t dim = 0;
    if (!parse_uint(rest[0], dim) || dim < 3 || dim > 16) bad("OFF: bad dimension");
    dimension = dim;
    rest.erase(rest.begin());
  }
  if (rest.empty() && !next_content_line(bytes, pos, rest)) bad("OFF: missing vertex/face counts");
  uint64_t nv = 0, nf = 0;
  if (rest.size() < 2 || !parse_uint(rest[0], nv) || !parse_uint(rest[1], nf))
    bad("OFF: malformed vertex/face counts");
  // Every vertex and face line takes at least 4 bytes ("1 0\n"): a larger count is a lying
  // header, refused with a clear message (the walk below would refuse it too).
  const uint64_t lines_possible = (bytes.size() - pos) / 4 + 1;
  if (nv > lines_possible || nf > lines_possible || nv + nf > lines_possible)
    bad("corrupt header: OFF declares " + std::to_string(nv) + " vertices and " +
        std::to_string(nf) + " faces, more than the file's " + std::to_string(bytes.size()) +
        " bytes can hold");

  MeshFileCounts counts;
  counts.vertices = nv;
  for (uint64_t v = 0; v < nv; ++v) {
    if (!next_content_line(bytes, pos, t))
      bad("OFF: the file ends after " + std::to_string(v) + " of " + std::to_string(nv) +
          " vertices");
    if (t.size() < dimension) bad("OFF: vertex " + std::to_string(v) + " has too few coordinates");
    for (size_t k = 0; k < dimension; ++k)
      if (!parse_number(t[k]))
        bad("OFF: vertex " + std::to_string(v) + " is not numeric");
      else if (k < 3 && !parse_coordinate(t[k]))
        bad("OFF: vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
  }
  for (uint64_t f = 0; f < nf; ++f) {
    if (!next_content_line(bytes, pos, t))
      bad("OFF: the file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    uint64_t n = 0;
    if (!parse_uint(t[0], n)) bad("OFF: face " + std::to_string(f) + " has no index count");
    if (n == 0) bad("OFF: face " + std::to_string(f) + " has no vertex indices");
    if (t.size() < n + 1) bad("OFF: face " + std::to_string(f) + " lists too few indices");
    for (uint64_t k = 1; k <= n; ++k) {
      uint64_t index = 0;
      if (!parse_uint(t[k], index) || index >= nv)
        bad("OFF: face " + std::to_string(f) + " has vertex index " + quote(t[k]) +
            " (the file has " + std::to_string(nv) + " vertices)");
    }
    add_face(counts, n);
  }
  return counts;
}

/// OBJ: every statement checked before assimp parses it (its parser corrupts its own heap on
/// some malformed files: fuzzing found it). Vertex data must be numbers, and every face, line and
/// point reference `v`, `v/t`, `v//n` or `v/t/n` a nonzero index within the elements defined so
/// far (negative: relative to the end, as the format allows). Grouping, smoothing and material
/// statements pass; any other statement is refused by name.
/// An OBJ line: ends at LF, CR LF or a lone CR (old Mac files), as assimp's OBJ parser reads it.
bool next_obj_line(std::string_view bytes, size_t& pos, std::string_view& line) {
  if (pos >= bytes.size()) return false;
  const size_t end = bytes.find_first_of("\r\n", pos);
  const size_t stop = end == std::string_view::npos ? bytes.size() : end;
  line = bytes.substr(pos, stop - pos);
  pos = stop + (stop + 1 < bytes.size() && bytes[stop] == '\r' && bytes[stop + 1] == '\n' ? 2 : 1);
  return true;
}

void validate_obj(std::string_view bytes) {
  uint64_t defined[3] = {0, 0, 0};  // v, vt, vn so far
  size_t pos = 0, line_no = 0;
  std::string_view line;
  const auto where = [&] { return "OBJ line " + std::to_string(line_no) + ": "; };
  const auto check_ref = [&](std::string_view ref) {
    std::string_view parts[3];
    int n = 0;
    size_t start = 0;
    for (size_t i = 0; i <= ref.size(); ++i)
      if (i == ref.size() || ref[i] == '/') {
        if (n == 3) bad(where() + "a vertex reference has more than three indices");
        parts[n++] = ref.substr(start, i - start);
        start = i + 1;
      }
    for (int k = 0; k < n; ++k) {
      if (parts[k].empty() && k > 0) continue;  // v//n, v/t/ are the format's omissions
      int64_t index = 0;
      if (!parse_int(parts[k], index) || index == 0)
        bad(where() + "bad vertex reference " + quote(ref, 40));
      const uint64_t magnitude =
          index < 0 ? static_cast<uint64_t>(-(index + 1)) + 1 : static_cast<uint64_t>(index);
      if (magnitude > defined[k])
        bad(where() + "vertex reference " + quote(ref, 40) + " beyond the " +
            std::to_string(defined[k]) + " defined so far");
    }
  };
  std::vector<std::string_view> t;
  while (next_obj_line(bytes, pos, line)) {
    ++line_no;
    const size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    split(line, t);
    if (t.empty()) continue;
    const std::string_view key = t[0];
    const auto numbers = [&](size_t lo, size_t hi) {
      if (t.size() - 1 < lo || t.size() - 1 > hi)
        bad(where() + quote(key) + " takes " + std::to_string(lo) + "-" + std::to_string(hi) +
            " numbers");
      for (size_t k = 1; k < t.size(); ++k)
        if (!parse_number(t[k])) bad(where() + quote(t[k], 40) + " is not a number");
    };
    if (key == "v") {
      numbers(3, 7);  // x y z [w], or x y z r g b
      for (size_t k = 1; k <= 3; ++k)
        if (!parse_coordinate(t[k])) bad(where() + "NaN or infinite vertex coordinate");
      ++defined[0];
    } else if (key == "vt") {
      numbers(1, 3);
      ++defined[1];
    } else if (key == "vn") {
      numbers(3, 3);
      ++defined[2];
    } else if (key == "f" || key == "l" || key == "p") {
      if (t.size() < (key == "f" ? 4u : 2u))
        bad(where() + quote(key) + " has too few vertex references");
      for (size_t k = 1; k < t.size(); ++k) check_ref(t[k]);
    } else if (key != "o" && key != "g" && key != "s" && key != "usemtl" && key != "mtllib" &&
               key != "mg") {
      bad(where() + "unsupported statement " + quote(key, 40));
    }
  }
}

/// Binary STL (80-byte header, a uint32 count, 50 bytes per facet) when the size says so, as assimp
/// decides; otherwise ASCII, read statement by statement: solid … { facet normal n n n / outer
/// loop / vertex x y z ×3 / endloop / endfacet } … endsolid, several solids allowed. Assimp's
/// ASCII reader skips what it does not understand and reads numbers without checking them.
MeshFileCounts validate_stl(std::string_view bytes) {
  MeshFileCounts counts;
  if (bytes.size() >= 84) {
    uint32_t facets = 0;
    std::memcpy(&facets, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50 * static_cast<uint64_t>(facets)) {
      if (facets == 0) bad("binary STL: no facets");
      for (uint64_t f = 0; f < facets; ++f)
        for (int k = 0; k < 12; ++k) {  // normal and three vertices
          float value = 0.0f;
          std::memcpy(&value, bytes.data() + 84 + 50 * f + 4 * k, 4);
          if (!std::isfinite(value))
            bad("binary STL facet " + std::to_string(f) + ": a coordinate is not finite");
        }
      counts.vertices = 3 * static_cast<size_t>(facets);
      counts.faces = counts.triangles = facets;
      return counts;
    }
  }
  size_t pos = 0, line_no = 0;
  std::string_view line;
  enum class At { outside, solid, facet, loop, loop_done, facet_done };
  At at = At::outside;
  int vertices = 0;
  const auto where = [&] { return "ASCII STL line " + std::to_string(line_no) + ": "; };
  const auto expect = [&](bool ok, std::string_view what) {
    if (!ok) bad(where() + "expected " + std::string(what));
  };
  std::vector<std::string_view> t;
  while (next_line(bytes, pos, line)) {
    ++line_no;
    split(line, t);
    if (t.empty()) continue;
    const std::string_view key = t[0];
    const auto numbers = [&](size_t first) {
      expect(t.size() == first + 3, "three numbers after " + std::string(key));
      for (size_t k = first; k < t.size(); ++k)
        if (!parse_number(t[k])) bad(where() + quote(t[k], 40) + " is not a number");
    };
    if (key == "solid") {
      expect(at == At::outside, "'endsolid' before a new 'solid'");
      at = At::solid;
    } else if (key == "endsolid") {
      expect(at == At::solid, "'endfacet' before 'endsolid'");
      at = At::outside;
    } else if (key == "facet") {
      expect(at == At::solid, "'facet' inside a solid");
      expect(t.size() > 1 && t[1] == "normal", "'facet normal'");
      numbers(2);
      at = At::facet;
    } else if (key == "outer") {
      expect(at == At::facet && t.size() == 2 && t[1] == "loop", "'outer loop' after 'facet'");
      at = At::loop;
      vertices = 0;
    } else if (key == "vertex") {
      expect(at == At::loop && vertices < 3, "at most three vertices inside 'outer loop'");
      numbers(1);
      for (size_t k = 1; k < t.size(); ++k)
        if (!parse_coordinate(t[k])) bad(where() + "NaN or infinite vertex coordinate");
      ++vertices;
    } else if (key == "endloop") {
      expect(at == At::loop && vertices == 3, "three vertices before 'endloop'");
      at = At::loop_done;
    } else if (key == "endfacet") {
      expect(at == At::loop_done, "'endloop' before 'endfacet'");
      at = At::solid;
      ++counts.faces;
    } else {
      bad(where() + "unknown statement " + quote(key, 40));
    }
  }
  if (line_no == 0 || at != At::outside)
    bad(at == At::outside ? "STL: the file is empty" : "ASCII STL: the file ends inside a solid");
  if (counts.faces == 0) bad("ASCII STL: no facets");
  counts.vertices = 3 * counts.faces;
  counts.triangles = counts.faces;
  return counts;
}

}  // namespace

std::optional<MeshFileCounts> validate_mesh_file(std::string_view bytes,
                                                 std::string_view extension) {
  if (bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 5) == "ply\r\n") return validate_ply(bytes);
  if (extension == ".ply") bad("PLY: the file does not start with 'ply'");
  if (extension == ".off") return validate_off(bytes);
  if (extension == ".obj") validate_obj(bytes);  // no counts: lines and points are dropped later
  if (extension == ".stl") return validate_stl(bytes);
  return std::nullopt;
}

}  // namespace penumbra
