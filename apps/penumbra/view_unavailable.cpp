// `penumbra view` in a build without the viewer (GLFW or Dear ImGui missing at configure time):
// the command exists and says how to get it.
#ifndef PENUMBRA_HAVE_VIEWER
#include "commands.hpp"
#include "penumbra/core/error.hpp"

namespace penumbra::cli {

void add_view_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("view", "Show a scene in a window (not in this build)");
  cmd->allow_extras();
  cmd->callback([] {
    throw Error(
        "view: this build has no viewer (install libglfw3-dev and libimgui-dev, then rebuild)");
  });
}

}  // namespace penumbra::cli
#endif
