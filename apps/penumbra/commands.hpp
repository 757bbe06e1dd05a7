// The CLI's subcommands. Each adds itself to the CLI11 app with a callback that does the work.
#pragma once

#include <CLI/CLI.hpp>

namespace penumbra::cli {

void add_render_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_list_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_scene_command(CLI::App& app);
/// `view`: the interactive window (viewer/), or a command that says the build has none.
void add_view_command(CLI::App& app);

}  // namespace penumbra::cli
