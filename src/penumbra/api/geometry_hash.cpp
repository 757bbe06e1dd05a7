#include "penumbra/api/geometry_hash.hpp"

#include <cstring>
#include <string>
#include <vector>

namespace penumbra {

namespace {

class Fnv1a {
 public:
  /// Eight bytes a step: each step (xor, then a multiplication by an odd number) is a bijection
  /// of the state, so any one changed word always changes the hash.
  void bytes(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    size_t i = 0;
    for (; i + 8 <= size; i += 8) {
      uint64_t word;
      std::memcpy(&word, p + i, 8);
      hash_ = (hash_ ^ word) * 0x100000001b3ull;
    }
    for (; i < size; ++i) hash_ = (hash_ ^ p[i]) * 0x100000001b3ull;
  }
  template <typename T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  template <typename T>
  void vector(const std::vector<T>& v) {
    value(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  void string(const std::string& s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  uint64_t get() const { return hash_; }

 private:
  uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

uint64_t geometry_hash(const Scene& scene) {
  Fnv1a h;
  h.value(scene.origin);
  h.value(scene.meshes.size());
  for (const Mesh& m : scene.meshes) {
    h.vector(m.positions);
    h.vector(m.normals);
    h.vector(m.uvs);
    h.vector(m.triangles);
    h.value(m.material);
    h.value(m.casts_shadows);
    h.value(m.receives_shadows);
  }
  h.value(scene.materials.size());
  for (const Material& m : scene.materials) {
    h.value(m.albedo);
    h.value(m.alpha_texture);
    h.value(m.transmittance);
  }
  h.value(scene.textures.size());
  for (const Texture& t : scene.textures) {
    h.value(t.width);
    h.value(t.height);
    h.value(t.channels);
    h.vector(t.texels);
  }
  return h.get();
}

}  // namespace penumbra
