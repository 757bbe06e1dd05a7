#include "penumbra/scene/mesh_loader.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <exception>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/scene/gltf_header.hpp"
#include "penumbra/scene/md2_file.hpp"
#include "penumbra/scene/mesh_header.hpp"
#include "penumbra/scene/off_reader.hpp"

namespace penumbra {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& reason) {
  throw Error("cannot load mesh " + quote(path.string(), 200) + ": " + reason);
}

/// One use of an aiMesh by a node, with the node's accumulated transform.
struct MeshInstance {
  const aiMesh* mesh;
  aiMatrix4x4 transform;
};

void collect_instances(const aiScene& scene, const aiNode* node, const aiMatrix4x4& parent,
                       std::vector<MeshInstance>& out, int depth) {
  // validate_gltf bounds the depth of the only hierarchical format read; stay safe anyway.
  if (!node || depth > kMaxGltfNodeDepth) return;
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const unsigned index = node->mMeshes[i];
    if (index < scene.mNumMeshes && scene.mMeshes[index]) {
      out.push_back({scene.mMeshes[index], transform});
    }
  }
  for (unsigned i = 0; i < node->mNumChildren; ++i) {
    collect_instances(scene, node->mChildren[i], transform, out, depth + 1);
  }
}

bool is_triangle_mesh(const aiMesh& mesh) {
  return (mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) != 0 && mesh.mNumFaces > 0 &&
         mesh.mVertices != nullptr;
}

Mesh merge(const std::filesystem::path& path, const std::vector<MeshInstance>& instances) {
  bool keep_normals = true, keep_uvs = true;
  size_t vertex_count = 0;
  for (const MeshInstance& inst : instances) {
    keep_normals = keep_normals && inst.mesh->HasNormals();
    keep_uvs = keep_uvs && inst.mesh->HasTextureCoords(0);
    vertex_count += inst.mesh->mNumVertices;
  }
  if (vertex_count > std::numeric_limits<uint32_t>::max()) fail(path, "too many vertices");

  Mesh out;
  out.name = path.stem().string();
  out.positions.reserve(vertex_count);
  if (keep_normals) out.normals.reserve(vertex_count);
  if (keep_uvs) out.uvs.reserve(vertex_count);

  for (const MeshInstance& inst : instances) {
    const aiMesh& m = *inst.mesh;
    const aiMatrix4x4& t = inst.transform;
    // Normals transform with the inverse transpose of the upper 3×3.
    aiMatrix3x3 normal_matrix(t);
    normal_matrix.Inverse().Transpose();
    // A mirroring transform reverses the winding; flip it back so faces keep their orientation.
    const bool mirrored = aiMatrix3x3(t).Determinant() < 0.0f;

    const uint32_t base = static_cast<uint32_t>(out.positions.size());
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
      const aiVector3D p = t * m.mVertices[v];
      const Vec3 pos(p.x, p.y, p.z);
      if (!is_finite(pos)) fail(path, "vertex " + std::to_string(v) + " is NaN or infinite");
      out.positions.push_back(pos);
      if (keep_normals) {
        const aiVector3D n = normal_matrix * m.mNormals[v];
        out.normals.emplace_back(n.x, n.y, n.z);
      }
      if (keep_uvs) out.uvs.emplace_back(m.mTextureCoords[0][v].x, m.mTextureCoords[0][v].y);
    }
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3 || !face.mIndices) continue;  // stray points/lines
      Triangle tri{};
      for (int c = 0; c < 3; ++c) {
        const unsigned idx = face.mIndices[c];
        if (idx >= m.mNumVertices) fail(path, "face index out of range");
        tri.v[c] = base + idx;
      }
      if (mirrored) std::swap(tri.v[1], tri.v[2]);
      out.triangles.push_back(tri);
    }
  }
  if (out.triangles.empty()) fail(path, "the file has no triangles");
  if (std::all_of(out.triangles.begin(), out.triangles.end(),
                  [&](const Triangle& t) { return is_degenerate(out, t); }))
    fail(path, "every triangle of the file has zero area");

  // Unit shading normals; a file with unusable (zero or non-finite) normals falls back to flat
  // shading rather than feeding NaNs to the renderer.
  for (Vec3& n : out.normals) {
    const float len = glm::length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) {
      out.normals.clear();
      break;
    }
    n /= len;
  }
  return out;
}

}  // namespace

std::string read_mesh_file_bytes(const std::filesystem::path& path) {
  require_regular_file(path, "cannot load mesh");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");
  // One read of the whole file (a stringstream would grow and copy it several times).
  std::string text;
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size < std::numeric_limits<size_t>::max() / 2) {
    text.resize(static_cast<size_t>(size));
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<size_t>(in.gcount()));
  }
  // Whatever the size query missed (a file growing while read) is appended.
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0)
    text.append(chunk, static_cast<size_t>(in.gcount()));
  if (in.bad()) fail(path, "cannot read the file");
  return text;
}

namespace {

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

/// The formats Penumbra reads: those it validates before assimp parses them. Assimp's other
/// importers trust their files (a 232-byte HL1 .mdl makes one allocate 12 GB).
constexpr const char* kMeshExtensions[] = {".obj", ".ply", ".off", ".stl", ".gltf", ".glb", ".md2"};

void require_supported_format(const std::filesystem::path& path, const std::string& extension) {
  for (const char* e : kMeshExtensions)
    if (extension == e) return;
  fail(path,
       "unsupported format " + quote(extension.empty() ? path.filename().string() : extension, 40) +
           " (Penumbra reads .obj, .ply, .off, .stl, .gltf, .glb and .md2; convert others, e.g. "
           "with assimp export)");
}

/// The bytes assimp reads instead of the file (a rewritten document), with its format.
struct ImportSource {
  std::string_view bytes;
  const char* format_hint;
};

Mesh import_mesh(const std::filesystem::path& path, const std::optional<MeshFileCounts>& counts,
                 const std::optional<ImportSource>& source);

}  // namespace

Mesh load_mesh_file(const std::filesystem::path& path) {
  // A plain OFF file is read directly, to assimp's mesh (off_reader.hpp: its subset is strict, so
  // it checks all the validation would). OFF, PLY, OBJ and STL files are otherwise validated in
  // full before assimp sees them (mesh_header.hpp).
  std::optional<MeshFileCounts> counts;
  try {
    require_regular_file(path, "cannot load mesh");  // first: a FIFO says so whatever its name
    const std::string extension = lowercase_extension(path);
    require_supported_format(path, extension);
    const std::string bytes = read_mesh_file_bytes(path);
    if (extension == ".md2") return read_md2(path, bytes).rest;
    if (extension == ".off")
      if (std::optional<Mesh> mesh = read_plain_off(bytes, path.stem().string()))
        return std::move(*mesh);
    if (extension == ".gltf" || extension == ".glb")
      counts = validate_gltf(bytes, extension == ".glb");
    else
      counts = validate_mesh_file(bytes, extension);
    if (extension == ".off")
      if (std::optional<std::string> obj = off_polygons_as_obj(bytes))
        return import_mesh(path, counts, ImportSource{*obj, "obj"});
  } catch (const Error& e) {
    if (std::string_view(e.what()).rfind("cannot load mesh", 0) == 0) throw;
    fail(path, e.what());
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory reading the file");
  }
  return import_mesh_file(path, counts);
}

Mesh import_mesh_file(const std::filesystem::path& path,
                      const std::optional<MeshFileCounts>& counts) {
  return import_mesh(path, counts, std::nullopt);
}

namespace {

Mesh import_mesh(const std::filesystem::path& path, const std::optional<MeshFileCounts>& counts,
                 const std::optional<ImportSource>& source) {
  try {
    Assimp::Importer importer;
    // Drop point and line primitives entirely (SortByPType then leaves triangle meshes only).
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                           aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    const aiScene* scene =
        source ? importer.ReadFileFromMemory(source->bytes.data(), source->bytes.size(), flags,
                                             source->format_hint)
               : importer.ReadFile(path.string(), flags);
    if (!scene) {
      std::string reason = importer.GetErrorString();
      if (reason.empty()) reason = "unknown assimp error";
      fail(path, reason);
    }
    if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || scene->mNumMeshes == 0 || !scene->mRootNode)
      fail(path, "the file contains no meshes");

    std::vector<MeshInstance> instances;
    collect_instances(*scene, scene->mRootNode, aiMatrix4x4(), instances, 0);
    std::erase_if(instances, [](const MeshInstance& i) { return !is_triangle_mesh(*i.mesh); });
    if (instances.empty()) fail(path, "the file has no triangles");
    Mesh mesh = merge(path, instances);
    // Assimp must have read what the validated file holds: no clamped or invented faces.
    if (counts && mesh.triangles.size() != counts->triangles)
      fail(path, "assimp read " + std::to_string(mesh.triangles.size()) +
                     " triangles where the file holds " + std::to_string(counts->triangles) +
                     " (it drops faces with an index beyond the vertex count)");
    return mesh;
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory (corrupt size field?)");
  } catch (const std::exception& e) {
    fail(path, e.what());
  } catch (...) {
    fail(path, "unknown assimp failure");
  }
}

}  // namespace

}  // namespace penumbra
