// libFuzzer target: the JSON scene parser and scene validation. Every input must end in a loaded
// scene or a penumbra::Error — any other exception, crash, hang or sanitizer report is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // load_scene_file reads a path (mesh and texture paths resolve beside it): one scratch file per
  // fuzzing process.
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("penumbra_fuzz_scene_" + std::to_string(::getpid()) + ".json");
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    penumbra::load_scene_file(path);
  } catch (const penumbra::Error&) {
    // the documented answer to bad input
  }
  return 0;
}
