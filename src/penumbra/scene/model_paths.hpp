// Where fetched models live: $PENUMBRA_MODELS, else $XDG_CACHE_HOME/penumbra/models, else
// ~/.cache/penumbra/models (scripts/fetch-models.sh fills it; nothing is committed).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace penumbra {

std::filesystem::path models_dir();
/// The path of `file_name` under models_dir() (searched recursively), if present.
std::optional<std::filesystem::path> find_model(const std::string& file_name);

}  // namespace penumbra
