#include "penumbra/scene/gltf_header.hpp"

#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"

namespace penumbra {

namespace {

using json = nlohmann::json;

[[noreturn]] void bad(const std::string& what) {
  throw Error("glTF: " + what);
}

uint32_t u32(std::string_view bytes, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;  // little-endian hosts only, as the project targets
}

/// The JSON chunk of a GLB container (magic, version 2, total length, then a JSON chunk first).
std::string_view glb_json(std::string_view bytes) {
  if (bytes.size() < 20 || bytes.substr(0, 4) != "glTF") bad("not a GLB file (no 'glTF' magic)");
  if (u32(bytes, 4) != 2) bad("GLB version " + std::to_string(u32(bytes, 4)) + " (expected 2)");
  if (u32(bytes, 8) != bytes.size())
    bad("the GLB header's length " + std::to_string(u32(bytes, 8)) + " is not the file's " +
        std::to_string(bytes.size()) + " bytes");
  const uint64_t length = u32(bytes, 12);
  if (u32(bytes, 16) != 0x4E4F534Au || length > bytes.size() - 20)
    bad("the first GLB chunk is not a JSON chunk within the file");
  return bytes.substr(20, length);
}

const json* find(const json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

/// An index into array `key` of the top level, or -1 when `v` is absent.
int64_t index_into(const json& root, const json* v, const char* key, const std::string& who) {
  if (!v) return -1;
  const json* array = find(root, key);
  if (!v->is_number_integer() || !array || !array->is_array() || v->get<int64_t>() < 0 ||
      v->get<int64_t>() >= static_cast<int64_t>(array->size()))
    bad(who + " refers to a missing " + std::string(key) + " entry");
  return v->get<int64_t>();
}

/// Triangles of one mesh (every primitive a triangle list), checking its accessors; nullopt when
/// a primitive is not a plain triangle list.
std::optional<uint64_t> mesh_triangles(const json& root, int64_t m) {
  const json& mesh = root["meshes"][m];
  const json* prims = find(mesh, "primitives");
  if (!prims || !prims->is_array()) bad("mesh " + std::to_string(m) + " has no primitives array");
  const json& accessors = root.contains("accessors") ? root["accessors"] : json::array();
  std::optional<uint64_t> total = 0;
  for (size_t p = 0; p < prims->size(); ++p) {
    const json& prim = (*prims)[p];
    const std::string who = "mesh " + std::to_string(m) + " primitive " + std::to_string(p);
    if (!prim.is_object()) bad(who + " is not an object");
    const json* mode = find(prim, "mode");
    const int64_t kind = mode && mode->is_number_integer() ? mode->get<int64_t>() : 4;
    if (kind <= 3) continue;  // points and lines: dropped, as documented
    const json* attributes = find(prim, "attributes");
    const json* position =
        attributes && attributes->is_object() ? find(*attributes, "POSITION") : nullptr;
    if (!position) bad(who + " has no POSITION attribute");
    const json& pos = accessors[index_into(root, position, "accessors", who + " POSITION")];
    if (pos.value("type", "") != "VEC3" || pos.value("componentType", 0) != 5126)
      bad(who + ": POSITION must be a float VEC3 accessor (got " + pos.value("type", "?") + ")");
    const uint64_t vertices = pos.value("count", uint64_t{0});
    uint64_t corners = vertices;
    if (const json* indices = find(prim, "indices")) {
      const json& ind = accessors[index_into(root, indices, "accessors", who + " indices")];
      corners = ind.value("count", uint64_t{0});
      if (kind == 4 && corners % 3 != 0)
        bad(who + ": " + std::to_string(corners) + " indices, not a multiple of 3");
      if (const json* max = find(ind, "max");
          max && max->is_array() && max->size() == 1 && (*max)[0].is_number() &&
          (*max)[0].get<double>() >= static_cast<double>(vertices))
        bad(who + ": index " + (*max)[0].dump() + " beyond its " + std::to_string(vertices) +
            " vertices");
      if (ind.contains("sparse")) total = std::nullopt;
    } else if (kind == 4 && vertices % 3 != 0) {
      bad(who + ": " + std::to_string(vertices) + " vertices, not a multiple of 3");
    }
    if (kind != 4 || pos.contains("sparse") || prim.contains("extensions")) total = std::nullopt;
    if (total) *total += corners / 3;
  }
  return total;
}

}  // namespace

std::optional<MeshFileCounts> validate_gltf(std::string_view bytes, bool glb) {
  const std::string_view text = glb ? glb_json(bytes) : bytes;
  json root;
  try {
    root = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {
    bad(std::string("invalid JSON (") + e.what() + ")");
  }
  if (!root.is_object()) bad("the document is not a JSON object");
  const json nodes = root.contains("nodes") ? root["nodes"] : json::array();
  if (!nodes.is_array()) bad("'nodes' is not an array");
  const size_t n = nodes.size();

  // Parents, checked in range and unique (the glTF node hierarchy is a forest).
  std::vector<int64_t> parent(n, -1);
  for (size_t i = 0; i < n; ++i) {
    if (!nodes[i].is_object()) bad("node " + std::to_string(i) + " is not an object");
    const json* children = find(nodes[i], "children");
    if (!children) continue;
    if (!children->is_array()) bad("node " + std::to_string(i) + ": children is not an array");
    for (const json& c : *children) {
      const int64_t k = index_into(root, &c, "nodes", "node " + std::to_string(i));
      if (parent[k] >= 0 || k == static_cast<int64_t>(i))
        bad("node " + std::to_string(k) + " has two parents or is its own child");
      parent[k] = static_cast<int64_t>(i);
    }
  }
  // Depth of every node by walking up to its root (a cycle never reaches one).
  std::vector<int> depth(n, -1);
  std::vector<size_t> chain;
  for (size_t i = 0; i < n; ++i) {
    chain.clear();
    int64_t k = static_cast<int64_t>(i);
    while (k >= 0 && depth[k] < 0) {
      chain.push_back(static_cast<size_t>(k));
      if (chain.size() > n) bad("the node hierarchy has a cycle");
      k = parent[k];
    }
    int d = k >= 0 ? depth[k] : -1;
    for (size_t c = chain.size(); c-- > 0;) {
      depth[chain[c]] = ++d;
      if (d > kMaxGltfNodeDepth)
        bad("node " + std::to_string(chain[c]) + " is " + std::to_string(d) +
            " levels deep (at most " + std::to_string(kMaxGltfNodeDepth) + " are read)");
    }
  }

  // Triangles of the default scene: every node under its roots that holds a mesh.
  std::vector<size_t> roots;
  const json* scenes = find(root, "scenes");
  if (scenes && scenes->is_array() && !scenes->empty()) {
    const json* which = find(root, "scene");
    const int64_t s = which ? index_into(root, which, "scenes", "'scene'") : 0;
    const json* list = find((*scenes)[s], "nodes");
    if (list && list->is_array())
      for (const json& r : *list) roots.push_back(index_into(root, &r, "nodes", "a scene"));
  } else {
    for (size_t i = 0; i < n; ++i)
      if (parent[i] < 0) roots.push_back(i);
  }
  std::vector<bool> in_scene(n, false);
  for (size_t r : roots) in_scene[r] = true;
  for (size_t i = 0; i < n; ++i) {  // parents come before children only by depth: walk up
    int64_t k = static_cast<int64_t>(i);
    while (k >= 0 && !in_scene[k]) k = parent[k];
    if (k >= 0) in_scene[i] = true;
  }
  std::optional<MeshFileCounts> counts = MeshFileCounts{};
  for (size_t i = 0; i < n; ++i) {
    const json* mesh = find(nodes[i], "mesh");
    if (!mesh) continue;
    const int64_t m = index_into(root, mesh, "meshes", "node " + std::to_string(i));
    const std::optional<uint64_t> t = mesh_triangles(root, m);
    if (!t) counts = std::nullopt;
    if (counts && in_scene[i]) counts->triangles += *t;
  }
  return counts;
}

}  // namespace penumbra
