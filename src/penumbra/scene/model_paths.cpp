#include "penumbra/scene/model_paths.hpp"

#include <cstdlib>
#include <system_error>

namespace penumbra {

std::filesystem::path models_dir() {
  if (const char* env = std::getenv("PENUMBRA_MODELS"); env && *env) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "penumbra" / "models";
  const char* home = std::getenv("HOME");
  return std::filesystem::path(home ? home : ".") / ".cache" / "penumbra" / "models";
}

std::optional<std::filesystem::path> find_model(const std::string& file_name) {
  const std::filesystem::path dir = models_dir();
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return std::nullopt;
  if (std::filesystem::exists(dir / file_name, ec)) return dir / file_name;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (it->path().filename() == file_name) return it->path();
  }
  return std::nullopt;
}

}  // namespace penumbra
