// The page of an animated sequence (`penumbra render --frames`): OUT/index.html beside
// frames.json — the per-method summary with the temporal error, plots of each method's time,
// error against `exact` and temporal error per frame, and the sequence itself: the videos when
// ffmpeg made them, else a flip-book of the frames' beauty images. Self-contained apart from the
// images and videos it links (relative paths in OUT).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace penumbra {

/// The page for `frames_doc` (frames.json as render writes it). `videos`: beauty.mp4 per method
/// and compare.mp4 exist beside it.
std::string sequence_page_html(const nlohmann::json& frames_doc, bool videos);

}  // namespace penumbra
