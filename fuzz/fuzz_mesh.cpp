// libFuzzer target: the mesh loaders (OFF, PLY, OBJ, STL, glTF, GLB) through the project's
// validation and assimp. The first byte picks the format (its value mod 6: off, ply, obj, stl,
// gltf, glb); the rest is the file. The glTF seeds (tests/data/meshes/gltf) are small valid files
// of each structure the validation walks (indices, node hierarchies, several primitives, embedded
// and GLB buffers), so mutations reach past the header checks. Every input must end in a mesh or
// a penumbra::Error — any other exception, crash, hang or sanitizer report is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/mesh_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".off", ".ply", ".obj", ".stl", ".gltf", ".glb"};
  const std::string ext = kExtensions[data[0] % 6];
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("penumbra_fuzz_mesh_" + std::to_string(::getpid()) + ext);
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
  }
  try {
    penumbra::load_mesh_file(path);
  } catch (const penumbra::Error&) {
    // the documented answer to bad input
  }
  return 0;
}
