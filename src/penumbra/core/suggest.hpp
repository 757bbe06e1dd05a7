// "Did you mean ...?" for misspelled names (scene keys, methods, scenes, subcommands).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

/// Levenshtein distance (insertions, deletions, substitutions).
size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate `word` is most likely a typo of — a small edit distance (at most a third of its
/// length, at least 2), or one name a prefix of the other (fov, fov_deg) — or "" when none is.
std::string nearest_name(std::string_view word, const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" for nearest_name, or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace penumbra
