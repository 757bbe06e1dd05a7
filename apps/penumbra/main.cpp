// penumbra: render soft shadows with every method, compare them with the exact reference.
#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "penumbra/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Penumbra: soft shadows from area lights, every published method against an exact reference"};
  app.require_subcommand(1);
  penumbra::cli::add_render_command(app);
  penumbra::cli::add_compare_command(app);
  penumbra::cli::add_info_command(app);
  penumbra::cli::add_list_command(app);
  penumbra::cli::add_report_command(app);
  penumbra::cli::add_scene_command(app);
  try {
    app.parse(argc, argv);  // runs the chosen subcommand's callback
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const penumbra::Error& e) {
    std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
