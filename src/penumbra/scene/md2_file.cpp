#include "penumbra/scene/md2_file.hpp"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cstdint>
#include <cstring>
#include <map>

#include "penumbra/core/error.hpp"

namespace penumbra {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& reason) {
  throw Error("cannot load mesh " + quote(path.string(), 200) + ": " + reason);
}

// Quake II's limits (qfiles.h), which assimp's MD2 reader also applies.
constexpr int32_t kMaxTriangles = 4096, kMaxVertices = 2048, kMaxTexCoords = 2048, kMaxFrames = 512,
                  kMaxSkins = 32, kNormals = 162;
constexpr size_t kHeaderBytes = 68, kFrameHeaderBytes = 40, kTriangleBytes = 12;

struct Header {
  int32_t fields[17];
  int32_t skins() const { return fields[5]; }
  int32_t vertices() const { return fields[6]; }
  int32_t texcoords() const { return fields[7]; }
  int32_t triangles() const { return fields[8]; }
  int32_t glcmds() const { return fields[9]; }
  int32_t frames() const { return fields[10]; }
  int32_t frame_bytes() const { return fields[4]; }
  int32_t ofs_skins() const { return fields[11]; }
  int32_t ofs_st() const { return fields[12]; }
  int32_t ofs_tris() const { return fields[13]; }
  int32_t ofs_frames() const { return fields[14]; }
  int32_t ofs_glcmds() const { return fields[15]; }
};

int32_t read_i32(std::string_view b, size_t at) {
  uint32_t u = 0;
  for (int i = 3; i >= 0; --i) u = (u << 8) | static_cast<uint8_t>(b[at + i]);
  return static_cast<int32_t>(u);
}

int16_t read_i16(std::string_view b, size_t at) {
  return static_cast<int16_t>(
      static_cast<uint16_t>(static_cast<uint8_t>(b[at]) | (static_cast<uint8_t>(b[at + 1]) << 8)));
}

void require(bool ok, const std::string& what) {
  if (!ok) throw Error("MD2: " + what);
}

void check_range(std::string_view b, int32_t offset, int64_t count, int64_t item_bytes,
                 const char* what) {
  const int64_t end = static_cast<int64_t>(offset) + count * item_bytes;
  require(offset >= static_cast<int32_t>(kHeaderBytes) && end <= static_cast<int64_t>(b.size()),
          std::string(what) + " lie outside the file");
}

void check_counts(const Header& h) {
  require(h.vertices() >= 3 && h.vertices() <= kMaxVertices, "vertex count out of range");
  require(h.triangles() >= 1 && h.triangles() <= kMaxTriangles, "triangle count out of range");
  require(h.texcoords() >= 0 && h.texcoords() <= kMaxTexCoords, "texture coordinate count");
  require(h.frames() >= 1 && h.frames() <= kMaxFrames, "frame count out of range");
  require(h.skins() >= 0 && h.skins() <= kMaxSkins, "skin count out of range");
  require(h.glcmds() >= 0, "negative GL command count");
  require(h.frame_bytes() == static_cast<int32_t>(kFrameHeaderBytes) + 4 * h.vertices(),
          "frame size does not match the vertex count");
}

void check_triangles(std::string_view b, const Header& h) {
  for (int32_t t = 0; t < h.triangles(); ++t) {
    const size_t at = static_cast<size_t>(h.ofs_tris()) + static_cast<size_t>(t) * kTriangleBytes;
    for (int c = 0; c < 3; ++c) {
      const int16_t v = read_i16(b, at + 2 * c), st = read_i16(b, at + 6 + 2 * c);
      require(v >= 0 && v < h.vertices(),
              "triangle " + std::to_string(t) + " has a vertex index out of range");
      require(h.texcoords() == 0 || (st >= 0 && st < h.texcoords()),
              "triangle " + std::to_string(t) + " has a texture coordinate index out of range");
    }
  }
}

std::string frame_name(std::string_view b, const Header& h, int32_t f) {
  const size_t at = static_cast<size_t>(h.ofs_frames()) +
                    static_cast<size_t>(f) * static_cast<size_t>(h.frame_bytes()) + 24;
  const std::string_view raw = b.substr(at, 16);
  return std::string(raw.substr(0, std::min(raw.find('\0'), raw.size())));
}

void check_frames(std::string_view b, const Header& h) {
  for (int32_t f = 0; f < h.frames(); ++f) {
    const size_t at = static_cast<size_t>(h.ofs_frames()) +
                      static_cast<size_t>(f) * static_cast<size_t>(h.frame_bytes());
    for (int i = 0; i < 6; ++i) {
      float x;
      const int32_t bits = read_i32(b, at + 4 * i);
      std::memcpy(&x, &bits, sizeof x);
      require(std::isfinite(x), "frame " + std::to_string(f) + " has a NaN or infinite scale");
    }
    for (int32_t v = 0; v < h.vertices(); ++v)
      require(static_cast<uint8_t>(b[at + kFrameHeaderBytes + 4 * v + 3]) < kNormals,
              "frame " + std::to_string(f) + " has a normal index out of range");
  }
}

/// One keyframe through assimp: three vertices per triangle, in triangle order (no joining).
Mesh import_frame(const std::filesystem::path& path, std::string_view bytes, int frame) {
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_IMPORT_MD2_KEYFRAME, frame);
  const unsigned flags = aiProcess_Triangulate | aiProcess_ValidateDataStructure;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, "md2");
  if (!scene || scene->mNumMeshes != 1 || !scene->mMeshes[0] || !scene->mRootNode)
    fail(path,
         "assimp cannot read frame " + std::to_string(frame) + ": " + importer.GetErrorString());
  const aiMesh& m = *scene->mMeshes[0];
  const aiMatrix4x4& t = scene->mRootNode->mTransformation;
  Mesh out;
  for (unsigned v = 0; v < m.mNumVertices; ++v) {
    const aiVector3D p = t * m.mVertices[v];
    out.positions.emplace_back(p.x, p.y, p.z);
    if (!is_finite(out.positions.back()))
      fail(path, "frame " + std::to_string(frame) + " has NaN or infinite positions");
    if (m.HasNormals()) out.normals.emplace_back(m.mNormals[v].x, m.mNormals[v].y, m.mNormals[v].z);
    if (m.HasTextureCoords(0))
      out.uvs.emplace_back(m.mTextureCoords[0][v].x, m.mTextureCoords[0][v].y);
  }
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    if (face.mNumIndices != 3) continue;
    out.triangles.push_back({{face.mIndices[0], face.mIndices[1], face.mIndices[2]}});
  }
  return out;
}

/// Joins the corners of `frames` (same layout each) that agree in uv and in every frame's position.
Md2Model join_frames(std::vector<Mesh> frames) {
  const Mesh& first = frames.front();
  std::map<std::vector<float>, uint32_t> index_of;
  std::vector<uint32_t> remap(first.positions.size());
  std::vector<uint32_t> kept;
  for (size_t v = 0; v < first.positions.size(); ++v) {
    std::vector<float> key;
    key.reserve(2 + 3 * frames.size());
    if (!first.uvs.empty()) key.insert(key.end(), {first.uvs[v].x, first.uvs[v].y});
    for (const Mesh& f : frames)
      key.insert(key.end(), {f.positions[v].x, f.positions[v].y, f.positions[v].z});
    const auto [it, added] = index_of.emplace(std::move(key), static_cast<uint32_t>(kept.size()));
    if (added) kept.push_back(static_cast<uint32_t>(v));
    remap[v] = it->second;
  }
  Md2Model model;
  model.rest.triangles = first.triangles;
  for (Triangle& t : model.rest.triangles)
    for (uint32_t& v : t.v) v = remap[v];
  for (const Mesh& f : frames) {
    std::vector<Vec3> positions;
    for (uint32_t v : kept) positions.push_back(f.positions[v]);
    model.frames.push_back(std::move(positions));
  }
  model.rest.positions = model.frames.front();
  for (uint32_t v : kept) {
    if (!first.normals.empty()) model.rest.normals.push_back(first.normals[v]);
    if (!first.uvs.empty()) model.rest.uvs.push_back(first.uvs[v]);
  }
  return model;
}

}  // namespace

std::vector<std::string> validate_md2(std::string_view b) {
  require(b.size() >= kHeaderBytes, "shorter than its header");
  require(b.substr(0, 4) == "IDP2", "not an MD2 file (no IDP2 magic)");
  Header h{};
  for (int i = 0; i < 17; ++i) h.fields[i] = read_i32(b, 4 * static_cast<size_t>(i));
  require(h.fields[1] == 8, "version " + std::to_string(h.fields[1]) + " (expected 8)");
  check_counts(h);
  check_range(b, h.ofs_skins(), h.skins(), 64, "skins");
  check_range(b, h.ofs_st(), h.texcoords(), 4, "texture coordinates");
  check_range(b, h.ofs_tris(), h.triangles(), kTriangleBytes, "triangles");
  check_range(b, h.ofs_frames(), h.frames(), h.frame_bytes(), "frames");
  check_range(b, h.ofs_glcmds(), h.glcmds(), 4, "GL commands");
  check_triangles(b, h);
  check_frames(b, h);
  std::vector<std::string> names;
  for (int32_t f = 0; f < h.frames(); ++f) names.push_back(frame_name(b, h, f));
  return names;
}

Md2Model read_md2(const std::filesystem::path& path, std::string_view bytes) {
  std::vector<std::string> names;
  try {
    names = validate_md2(bytes);
  } catch (const Error& e) {
    fail(path, e.what());
  }
  std::vector<Mesh> frames;
  for (size_t f = 0; f < names.size(); ++f) {
    frames.push_back(import_frame(path, bytes, static_cast<int>(f)));
    const Mesh& a = frames.front();
    const Mesh& b = frames.back();
    if (b.positions.size() != a.positions.size() || b.uvs.size() != a.uvs.size() ||
        b.triangles.size() != a.triangles.size())
      fail(path, "assimp read frame " + std::to_string(f) + " with another layout than frame 0");
  }
  if (frames.front().triangles.empty()) fail(path, "the file has no triangles");
  Md2Model model = join_frames(std::move(frames));
  model.rest.name = path.stem().string();
  model.frame_names = std::move(names);
  return model;
}

}  // namespace penumbra
