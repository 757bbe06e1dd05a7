// `penumbra scene`: writes any scene (built-in, scene file or framed model) as a JSON scene file.
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "method_args.hpp"
#include "penumbra/scene/scene_file.hpp"
#include "penumbra/scene/scene_writer.hpp"

namespace penumbra::cli {

namespace {

struct SceneArgs {
  std::string scene;
  std::string out;
  std::string size;
  FramingArgs framing;
};

void run_scene(const SceneArgs& args) {
  Scene scene = load_scene(args.scene, to_framing(args.framing));
  if (!args.size.empty()) parse_size(args.size, scene.camera);
  write_scene_file(scene, args.out);
  std::printf("%s\n", args.out.c_str());
}

}  // namespace

void add_scene_command(CLI::App& app) {
  auto args = std::make_shared<SceneArgs>();
  CLI::App* cmd = app.add_subcommand(
      "scene", "Write a scene (built-in, scene file or model file) as a JSON scene file");
  cmd->add_option("--scene", args->scene, "Built-in scene name, scene .json file or model file")
      ->required();
  cmd->add_option("--out", args->out, "JSON file to write (meshes and textures go beside it)")
      ->required();
  cmd->add_option("--size", args->size, "Image size WxH written into the camera");
  add_framing_options(*cmd, args->framing);
  cmd->callback([args] { run_scene(*args); });
}

}  // namespace penumbra::cli
