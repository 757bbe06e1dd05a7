// Checks of `penumbra view` screenshots for tests/viewer/viewer_test.sh. The image is drawn at the
// window's top-left corner, each pixel as a SCALE × SCALE block; the panel is at its right.
//   viewer_probe match SHOT.png VIS.exr SCALE       the image shows V (visibility view) exactly
//   viewer_probe moved A.png B.png VA.exr VB.exr SCALE
//                                                   the screenshots differ where V changed (and
//                                                   only there)
//   viewer_probe panel SHOT.png X0                  the panel (x >= X0) is drawn, not blank
// Prints what it measured; exit 0 when the check holds, 1 when not, 2 on bad input.
#include <stb_image.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/io/image_io.hpp"

namespace {

using penumbra::Image;

struct Png {
  int width = 0, height = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> rgb{nullptr, stbi_image_free};
  const unsigned char* at(int x, int y) const {
    return rgb.get() + (static_cast<size_t>(y) * width + x) * 3;
  }
};

Png read_png(const char* path) {
  Png p;
  int n = 0;
  p.rgb.reset(stbi_load(path, &p.width, &p.height, &n, 3));
  if (!p.rgb) throw penumbra::Error(std::string("cannot read ") + path);
  return p;
}

Image<float> read_v(const char* path) {
  for (auto& layer : penumbra::read_exr(path))
    if (layer.name == "light0") return std::move(layer.pixels);
  throw penumbra::Error(std::string(path) + ": no light0 layer");
}

/// The grey of image pixel (x, y) in the screenshot (-1 when the pixel is not grey).
int grey(const Png& shot, int scale, int x, int y) {
  const unsigned char* c = shot.at(x * scale + scale / 2, y * scale + scale / 2);
  return c[0] == c[1] && c[1] == c[2] ? c[0] : -1;
}

int match(const Png& shot, const Image<float>& v, int scale) {
  int bad = 0;
  for (int y = 0; y < v.height(); ++y)
    for (int x = 0; x < v.width(); ++x)
      if (std::abs(grey(shot, scale, x, y) - penumbra::linear_to_srgb8(v(x, y))) > 1) ++bad;
  std::printf("match: %d of %zu pixels differ from V\n", bad, v.size());
  return bad == 0 ? 0 : 1;
}

int moved(const Png& a, const Png& b, const Image<float>& va, const Image<float>& vb, int scale) {
  int changed = 0, changed_shown = 0, still = 0, still_shown = 0;
  for (int y = 0; y < va.height(); ++y)
    for (int x = 0; x < va.width(); ++x) {
      const float dv = std::abs(va(x, y) - vb(x, y));
      const bool shown = std::abs(grey(a, scale, x, y) - grey(b, scale, x, y)) > 32;
      if (dv > 0.25f) {
        ++changed;
        changed_shown += shown;
      } else if (dv < 1.0f / 512.0f) {
        ++still;
        still_shown += shown;
      }
    }
  std::printf(
      "moved: V changed by > 0.25 at %d pixels, the screenshots differ at %d of them; "
      "V unchanged at %d pixels, the screenshots differ at %d of them\n",
      changed, changed_shown, still, still_shown);
  const bool ok =
      changed >= static_cast<int>(va.size() / 100) && changed_shown == changed && still_shown == 0;
  return ok ? 0 : 1;
}

int panel(const Png& shot, int x0) {
  std::map<int, int> colours;
  for (int y = 0; y < shot.height; ++y)
    for (int x = x0; x < shot.width; ++x) {
      const unsigned char* c = shot.at(x, y);
      ++colours[(c[0] << 16) | (c[1] << 8) | c[2]];
    }
  int most = 0, total = 0;
  for (const auto& [c, n] : colours) {
    most = std::max(most, n);
    total += n;
  }
  const double other = 1.0 - static_cast<double>(most) / std::max(total, 1);
  std::printf("panel: %zu colours, %.1f%% of the pixels not the commonest colour\n", colours.size(),
              100.0 * other);
  return colours.size() >= 16 && other >= 0.02 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string what = argc > 1 ? argv[1] : "";
    if (what == "match" && argc == 5)
      return match(read_png(argv[2]), read_v(argv[3]), std::atoi(argv[4]));
    if (what == "moved" && argc == 7)
      return moved(read_png(argv[2]), read_png(argv[3]), read_v(argv[4]), read_v(argv[5]),
                   std::atoi(argv[6]));
    if (what == "panel" && argc == 4) return panel(read_png(argv[2]), std::atoi(argv[3]));
    std::fprintf(stderr, "usage: viewer_probe match|moved|panel ... (see the source)\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viewer_probe: %s\n", e.what());
  }
  return 2;
}
