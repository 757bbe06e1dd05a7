#include "penumbra/pipeline/video.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"

extern char** environ;

namespace penumbra {

namespace fs = std::filesystem;

namespace {

constexpr const char* kLabelFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// The last non-empty line of a text file (ffmpeg's diagnostics), or "".
std::string last_line(const fs::path& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

/// Runs ffmpeg with `args` (no shell), its diagnostics into `log`; throws Error unless it exits 0.
void run_ffmpeg(const fs::path& ffmpeg, const std::vector<std::string>& args, const fs::path& log,
                const std::string& what) {
  std::vector<char*> argv;
  std::string program = ffmpeg.string();
  argv.push_back(program.data());
  std::vector<std::string> owned(args);
  for (std::string& a : owned) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw Error("cannot run " + quote(program, 200) + " for " + what + ": " +
                std::strerror(spawned));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw Error("waiting for ffmpeg: " + std::string(std::strerror(errno)));
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  const std::string why = WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                            : "signal " + std::to_string(WTERMSIG(status));
  throw Error("ffmpeg failed writing " + what + " (" + why + "): " + quote(last_line(log), 300));
}

/// The image2 demuxer reads `%` as a pattern character: a literal one is doubled.
std::string escape_pattern(const std::string& path) {
  std::string out;
  for (char c : path) out += c == '%' ? std::string("%%") : std::string(1, c);
  return out;
}

/// Numbers a method's frames 000000.png, 000001.png, ... in `links` (hard links, else copies):
/// the contiguous sequence ffmpeg's image2 input reads, whatever the range's step.
void link_frames(const fs::path& out, const std::string& method, const std::vector<int>& frames,
                 const fs::path& links) {
  fs::create_directories(links);
  for (size_t i = 0; i < frames.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%06zu.png", i);
    const fs::path from = out / method / frame_folder(frames[i]) / "beauty.png";
    std::error_code ec;
    fs::create_hard_link(from, links / name, ec);
    if (ec) fs::copy_file(from, links / name, fs::copy_options::overwrite_existing);
  }
}

/// ffmpeg's input arguments for one numbered folder.
std::vector<std::string> input_args(const fs::path& links, double fps) {
  return {"-framerate", std::to_string(fps), "-i", escape_pattern(links.string()) + "/%06d.png"};
}

/// H.264 in yuv420p (the format players accept), to `temporary` (its name has no .mp4).
std::vector<std::string> output_args(double fps, const fs::path& temporary) {
  return {"-c:v", "libx264", "-pix_fmt",        "yuv420p", "-r", std::to_string(fps),
          "-f",   "mp4",     temporary.string()};
}

/// One method's chain of the compare filter: even size (yuv420p), then the label.
std::string label_chain(size_t input, const std::string& method, bool font) {
  // Appended piece by piece (GCC 12 misreports "[" + string as overlapping).
  std::string chain = "[";
  chain += std::to_string(input);
  chain += ":v]pad=ceil(iw/2)*2:ceil(ih/2)*2";
  if (font) {
    chain += ",drawtext=fontfile=";
    chain += kLabelFont;
    chain += ":text=";
    chain += method;
    // Scaled to the frame (h/24, at least 9 px): legible at 64² and at 1024².
    chain +=
        ":x=4:y=4:fontsize=max(9\\,h/24):fontcolor=white:box=1:boxcolor=black@0.6:boxborderw=2";
  }
  chain += "[v";
  chain += std::to_string(input);
  chain += ']';
  return chain;
}

}  // namespace

std::optional<fs::path> find_executable(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return std::nullopt;
  std::string dirs(path);
  for (size_t begin = 0; begin <= dirs.size();) {
    size_t end = dirs.find(':', begin);
    if (end == std::string::npos) end = dirs.size();
    const fs::path candidate = fs::path(dirs.substr(begin, end - begin)) / name;
    std::error_code ec;
    if (end > begin && fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    begin = end + 1;
  }
  return std::nullopt;
}

std::string frame_folder(int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d", frame);
  return name;
}

void write_videos(const fs::path& ffmpeg, const fs::path& out,
                  const std::vector<std::string>& methods, const std::vector<int>& frames,
                  double fps) {
  const fs::path work = out / (".video-" + std::to_string(::getpid()));
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{work};
  const fs::path log = work / "ffmpeg.log";
  std::vector<std::string> compare = {"-y", "-v", "error"};
  for (size_t m = 0; m < methods.size(); ++m) {
    const fs::path links = work / std::to_string(m);
    link_frames(out, methods[m], frames, links);
    const fs::path mp4 = out / methods[m] / "beauty.mp4";
    write_file_atomically(mp4, [&](const fs::path& temporary) {
      std::vector<std::string> args = {"-y", "-v", "error"};
      for (std::string& a : input_args(links, fps)) args.push_back(std::move(a));
      for (std::string a : {"-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"}) args.push_back(a);
      for (std::string& a : output_args(fps, temporary)) args.push_back(std::move(a));
      run_ffmpeg(ffmpeg, args, log, quote(mp4.string(), 200));
    });
    for (std::string& a : input_args(links, fps)) compare.push_back(std::move(a));
  }
  const bool font = fs::is_regular_file(kLabelFont);
  std::string filter;
  for (size_t m = 0; m < methods.size(); ++m) filter += label_chain(m, methods[m], font) + ";";
  for (size_t m = 0; m < methods.size(); ++m) filter += "[v" + std::to_string(m) + "]";
  filter += methods.size() > 1 ? "hstack=inputs=" + std::to_string(methods.size()) + "[out]"
                               : "null[out]";
  const fs::path mp4 = out / "compare.mp4";
  write_file_atomically(mp4, [&](const fs::path& temporary) {
    std::vector<std::string> args = compare;
    for (std::string a : {"-filter_complex", filter.c_str(), "-map", "[out]"}) args.push_back(a);
    for (std::string& a : output_args(fps, temporary)) args.push_back(std::move(a));
    run_ffmpeg(ffmpeg, args, log, quote(mp4.string(), 200));
  });
}

}  // namespace penumbra
