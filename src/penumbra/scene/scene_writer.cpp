#include "penumbra/scene/scene_writer.hpp"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/io/image_io.hpp"
#include "penumbra/scene/animation_file.hpp"
#include "penumbra/scene/mesh_loader.hpp"

namespace penumbra {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

json vec3(const Vec3& v) {
  return json::array({v.x, v.y, v.z});
}

/// A position in the file's (world) coordinates: the scene's plus its origin, in double.
json position(const Vec3& v, const DVec3& origin) {
  if (origin == DVec3(0.0)) return vec3(v);
  const DVec3 w = DVec3(v) + origin;
  return json::array({w.x, w.y, w.z});
}

/// Row-major 16 numbers (the scene format's `matrix`), its translation moved by `origin`.
json matrix(const Mat4& m, const DVec3& origin) {
  json out = json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      if (c == 3 && r < 3 && origin != DVec3(0.0))
        out.push_back(double{m[c][r]} + origin[r]);
      else
        out.push_back(m[c][r]);
    }
  return out;
}

/// Is the mesh still what its source file and transform give (bit for bit)?
bool matches_source(const Mesh& mesh) {
  if (mesh.source_file.empty() || !fs::exists(mesh.source_file)) return false;
  try {
    Mesh again = load_mesh_file(mesh.source_file);
    transform_mesh(again, mesh.source_transform);
    if (again.positions.size() != mesh.positions.size() ||
        again.triangles.size() != mesh.triangles.size() ||
        again.normals.size() != mesh.normals.size() || again.uvs.size() != mesh.uvs.size())
      return false;
    return std::memcmp(again.positions.data(), mesh.positions.data(),
                       mesh.positions.size() * sizeof(Vec3)) == 0 &&
           std::memcmp(again.triangles.data(), mesh.triangles.data(),
                       mesh.triangles.size() * sizeof(Triangle)) == 0;
  } catch (const Error&) {
    return false;
  }
}

template <typename T>
void put(std::ofstream& f, const T& v) {
  f.write(reinterpret_cast<const char*>(&v), sizeof v);
}

/// Binary little-endian PLY: assimp reads its floats back bit for bit (a text format would go
/// through assimp's approximate number parser).
void write_ply(const fs::path& path, const Mesh& m) {
  write_file_atomically(path, [&](const fs::path& temporary) {
    std::ofstream f(temporary, std::ios::binary);
    const bool normals = m.normals.size() == m.positions.size();
    const bool uvs = m.uvs.size() == m.positions.size();
    // Assimp skips a line feed right after end_header even in a binary body, and reads every
    // record a byte off (a first x of 0.02f is 0A D7 A3 3C): a leading byte property avoids it.
    const bool guard =
        !m.positions.empty() && (std::bit_cast<uint32_t>(m.positions[0].x) & 0xffu) == 0x0au;
    f << "ply\nformat binary_little_endian 1.0\ncomment written by penumbra scene\n"
      << "element vertex " << m.positions.size() << "\n"
      << (guard ? "property uchar guard\n" : "") << "property float x\nproperty float y\n"
      << "property float z\n";
    if (normals) f << "property float nx\nproperty float ny\nproperty float nz\n";
    if (uvs) f << "property float s\nproperty float t\n";
    f << "element face " << m.triangles.size() << "\nproperty list uchar uint vertex_indices\n"
      << "end_header\n";
    for (size_t i = 0; i < m.positions.size(); ++i) {
      if (guard) put(f, uint8_t{1});
      put(f, m.positions[i].x), put(f, m.positions[i].y), put(f, m.positions[i].z);
      if (normals) put(f, m.normals[i].x), put(f, m.normals[i].y), put(f, m.normals[i].z);
      if (uvs) put(f, m.uvs[i].x), put(f, m.uvs[i].y);
    }
    for (const Triangle& t : m.triangles) {
      put(f, static_cast<uint8_t>(3));
      for (uint32_t v : t.v) put(f, v);
    }
    // Buffered bytes reach the file system here: a full disk fails before the rename.
    f.close();
    if (!f) throw Error("cannot write " + quote(path.string(), 200) + ": " + std::strerror(errno));
  });
}

/// A texture as an 8-bit PNG: alpha masks as grey (the loader reads the first channel / 255),
/// emission as sRGB (the loader decodes sRGB), so textures read from 8-bit files come back exact.
void write_texture(const fs::path& path, const Texture& t, bool emission) {
  std::vector<uint8_t> rgb(static_cast<size_t>(t.width) * t.height * 3);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      // Texture row 0 is v = 0, the bottom of the image: PNG rows go top to bottom.
      const size_t o = (static_cast<size_t>(t.height - 1 - y) * t.width + x) * 3;
      for (int c = 0; c < 3; ++c) {
        const float v = t.channel(x, y, t.channels >= 3 ? c : 0);
        rgb[o + c] = emission ? linear_to_srgb8(v)
                              : static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255));
      }
    }
  write_png_rgb8(path, t.width, t.height, rgb);
}

/// The names meshes or lights are written under: their own, made unique (name_2, name_3, ...)
/// when the scene is animated, since the animation refers to them by name.
template <class Item>
std::vector<std::string> written_names(const std::vector<Item>& items, bool unique) {
  std::vector<std::string> names;
  std::set<std::string> used;
  for (const Item& item : items) {
    std::string name = item.name;
    if (unique) {
      if (name.empty()) name = "unnamed";
      for (int k = 2; used.count(name); ++k) name = item.name + "_" + std::to_string(k);
      used.insert(name);
    }
    names.push_back(name);
  }
  return names;
}

std::string file_safe(const std::string& name) {
  std::string out;
  for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return out.empty() ? "mesh" : out;
}

}  // namespace

void write_scene_file(const Scene& scene, const fs::path& json_path) {
  const fs::path base = json_path.parent_path().empty() ? fs::path(".") : json_path.parent_path();
  const std::string assets = json_path.stem().string() + "_meshes";
  std::error_code ec;
  fs::create_directories(base, ec);
  if (ec) throw Error("cannot create " + base.string() + ": " + ec.message());
  const auto asset_dir = [&] {
    fs::create_directories(base / assets, ec);
    if (ec) throw Error("cannot create " + (base / assets).string() + ": " + ec.message());
    return base / assets;
  };

  json j;
  const Camera& c = scene.camera;
  const DVec3& origin = scene.origin;
  j["camera"] = {{"position", position(c.position, origin)},
                 {"target", position(c.target, origin)},
                 {"up", vec3(c.up)},
                 {"fov_deg", c.vfov_deg},
                 {"width", c.width},
                 {"height", c.height}};
  j["ambient"] = vec3(scene.ambient);

  std::vector<std::string> texture_files(scene.textures.size());
  const auto texture_file = [&](int index, bool emission) {
    if (texture_files[index].empty()) {
      const std::string name =
          std::to_string(index) + "_" + file_safe(scene.textures[index].name) + ".png";
      write_texture(asset_dir() / name, scene.textures[index], emission);
      texture_files[index] = assets + "/" + name;
    }
    return texture_files[index];
  };

  std::vector<std::string> material_names;
  std::set<std::string> used;
  j["materials"] = json::array();
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    std::string name = m.name.empty() ? "material" : m.name;
    for (int k = 2; used.count(name); ++k) name = m.name + "_" + std::to_string(k);
    used.insert(name);
    material_names.push_back(name);
    json jm = {{"name", name}, {"albedo", vec3(m.albedo)}};
    if (m.alpha_texture >= 0) jm["alpha_texture"] = texture_file(m.alpha_texture, false);
    if (m.transmittance > 0.0f) jm["transmittance"] = m.transmittance;
    j["materials"].push_back(jm);
  }

  const bool animated = !scene.animation.empty();
  // A clip generated in code is written as vertex_keys, which the loader places by the mesh's
  // transform: such a mesh is written as its own PLY (transform: the identity), as its keys are.
  std::vector<bool> generated_clip(scene.meshes.size(), false);
  for (const MeshAnimation& a : scene.animation.meshes)
    if (a.clip && !(a.clip->source_fps > 0.0)) generated_clip[a.mesh] = true;
  std::vector<bool> written_as_file(scene.meshes.size(), false);
  const std::vector<std::string> mesh_names = written_names(scene.meshes, animated);
  const std::vector<std::string> light_names = written_names(scene.lights, animated);
  j["meshes"] = json::array();
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    const Mesh& m = scene.meshes[i];
    json jm = {{"name", mesh_names[i]},
               {"material", material_names.at(m.material)},
               {"casts_shadows", m.casts_shadows},
               {"receives_shadows", m.receives_shadows}};
    written_as_file[i] = !generated_clip[i] && matches_source(m);
    if (written_as_file[i]) {
      jm["file"] = m.source_file;
      if (m.source_transform != Mat4(1.0f) || origin != DVec3(0.0))
        jm["transform"] = {{"matrix", matrix(m.source_transform, origin)}};
    } else {
      const std::string name = std::to_string(i) + "_" + file_safe(m.name) + ".ply";
      write_ply(asset_dir() / name, m);
      jm["file"] = assets + "/" + name;
      if (origin != DVec3(0.0))
        jm["transform"] = {{"translate", json::array({origin.x, origin.y, origin.z})}};
    }
    j["meshes"].push_back(jm);
  }

  j["lights"] = json::array();
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    json jl = {{"type", std::string(to_string(l.shape))},
               {"name", light_names[i]},
               {"center", position(l.center, origin)},
               {"radiance", vec3(l.radiance)}};
    if (l.shape == LightShape::rect) {
      jl["edge_u"] = vec3(l.edge_u);
      jl["edge_v"] = vec3(l.edge_v);
      jl["two_sided"] = l.two_sided;
      if (l.emission_texture >= 0) jl["emission_texture"] = texture_file(l.emission_texture, true);
    } else if (l.shape == LightShape::disk) {
      jl["normal"] = vec3(l.normal);
      jl["radius"] = l.radius;
    } else if (l.shape == LightShape::sphere) {
      jl["radius"] = l.radius;
    }
    j["lights"].push_back(jl);
  }

  AnimationAssets animation_assets;
  animation_assets.mesh_names = mesh_names;
  animation_assets.light_names = light_names;
  animation_assets.mesh_written_as_file = written_as_file;
  animation_assets.emission_texture = [&](int texture) { return texture_file(texture, true); };
  animation_assets.clip_key = [&](int mesh, size_t key, const std::vector<Vec3>& positions) {
    Mesh frame = scene.meshes[mesh];
    frame.positions = positions;
    const std::string name =
        std::to_string(mesh) + "_" + file_safe(frame.name) + "_key" + std::to_string(key) + ".ply";
    write_ply(asset_dir() / name, frame);
    return assets + "/" + name;
  };
  if (json animation = animation_json(scene, animation_assets); !animation.is_null())
    j["animation"] = std::move(animation);

  write_text_file(json_path, j.dump(2) + "\n");
}

}  // namespace penumbra
