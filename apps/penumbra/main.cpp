// penumbra: render soft shadows with every method, compare them with the exact reference.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <vector>

#include "commands.hpp"
#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/core/progress.hpp"
#include "penumbra/core/simd.hpp"
#include "penumbra/core/suggest.hpp"

namespace {

/// The error contract: exactly one line on stderr, `penumbra:` first, control characters escaped,
/// long strings cut, on a fresh line even if a progress line was being drawn; exit status 1.
int fail(const std::string& message) {
  if (penumbra::stderr_line_open()) std::fputc('\n', stderr);
  std::fprintf(stderr, "penumbra: error: %s\n", penumbra::one_line(message).c_str());
  return 1;
}

/// CLI11 reports a mistyped subcommand as a stray positional argument ("The following arguments
/// were not expected") or as "A subcommand is required"; name the command and the nearest one.
std::string usage_message(const CLI::App& app, const CLI::ParseError& e, int argc, char** argv) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  if (app.get_subcommands().empty()) {
    if (argc > 1 && argv[1][0] != '-')
      return "unknown command " + penumbra::quote(argv[1]) +
             penumbra::did_you_mean(argv[1], names) + " (commands: " + list + ")";
    if (argc <= 1) return "a command is required (commands: " + list + "; see --help)";
  }
  const auto parsed = app.get_subcommands();
  const std::string who = parsed.empty() ? "" : parsed.front()->get_name() + ": ";
  if (!parsed.empty()) {
    // A mistyped long option (--sample for --samples) is the cause of the error, whichever CLI11
    // reports (unexpected arguments, or the option it stood for missing): name it and the nearest
    // option of the command.
    std::vector<std::string> options;
    for (const CLI::Option* option : parsed.front()->get_options())
      for (const std::string& name : option->get_lnames()) options.push_back("--" + name);
    for (int i = 2; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg.rfind("--", 0) != 0 || arg.size() == 2) continue;
      const std::string name = arg.substr(0, arg.find('='));
      if (std::find(options.begin(), options.end(), name) != options.end()) continue;
      return who + "unknown option " + penumbra::quote(name) +
             penumbra::did_you_mean(name, options) + " (see " + parsed.front()->get_name() +
             " --help)";
    }
  }
  return who + e.what() + " (see --help)";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Penumbra: soft shadows from area lights, every published method against an exact reference"};
  app.require_subcommand(1);
  app.option_defaults()->always_capture_default();  // --help shows every option's default
  penumbra::cli::add_render_command(app);
  penumbra::cli::add_compare_command(app);
  penumbra::cli::add_info_command(app);
  penumbra::cli::add_list_command(app);
  penumbra::cli::add_report_command(app);
  penumbra::cli::add_scene_command(app);
  penumbra::cli::add_view_command(app);
  try {
    penumbra::simd::configure_from_environment();
    // Ctrl-C or a kill while an output is written must not leave its hidden temporary behind.
    penumbra::remove_temporaries_on_signal();
    app.parse(argc, argv);  // runs the chosen subcommand's callback
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(usage_message(app, e, argc, argv));
  } catch (const penumbra::Error& e) {
    return fail(e.what());
  } catch (const std::bad_alloc&) {
    return fail("out of memory (try a smaller --size, fewer --samples or fewer methods)");
  } catch (const std::filesystem::filesystem_error& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what());
  } catch (...) {
    return fail("internal error: unknown exception");
  }
  // Tables and listings go to stdout: a full disk or a closed pipe there is a failure too.
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    return fail("cannot write to standard output");
  return 0;
}
