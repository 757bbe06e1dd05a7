// Outputs on a full disk: `report`'s text files (plot::write_text_file) and `scene`'s JSON and
// PLY files (write_scene_file) must fail with Error and leave nothing under the final name and no
// temporary, as `render`'s outputs do (core/files.hpp). A full disk is simulated in a child
// process by RLIMIT_FSIZE: a write past the limit fails with EFBIG, as one fails with ENOSPC.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/report/svg_plot.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/scene_writer.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

constexpr rlim_t kLimitBytes = 16384;

/// Runs `write` in a child process whose files cannot grow past kLimitBytes. Returns its exit
/// code: 0 it returned, 1 it threw Error, 3 anything else, -1 the child died.
int run_with_a_full_disk(const std::function<void()>& write) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // EFBIG instead of the signal
    const rlimit limit{kLimitBytes, kLimitBytes};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int code = 3;
    try {
      write();
      code = 0;
    } catch (const Error&) {
      code = 1;
    } catch (...) {
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class AtomicWrites : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("penumbra_atomic_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  /// Every file under the folder, relative, with its size.
  std::vector<std::pair<std::string, uintmax_t>> files() const {
    std::vector<std::pair<std::string, uintmax_t>> out;
    for (const auto& e : fs::recursive_directory_iterator(dir_))
      if (e.is_regular_file())
        out.emplace_back(fs::relative(e.path(), dir_).string(), e.file_size());
    return out;
  }
  fs::path dir_;
};

TEST_F(AtomicWrites, ReportTextFileLeavesNothingOnAFullDisk) {
  const std::string text(5 * kLimitBytes, 'x');
  EXPECT_EQ(run_with_a_full_disk([&] { plot::write_text_file(dir_ / "raytrace.json", text); }), 1);
  EXPECT_TRUE(files().empty()) << files().front().first << ", " << files().front().second
                               << " bytes";
  // The same write with room succeeds, whole.
  EXPECT_EQ(run_with_a_full_disk([&] { plot::write_text_file(dir_ / "small.json", "{}\n"); }), 0);
  ASSERT_EQ(files().size(), 1u);
  EXPECT_EQ(files().front().second, 3u);
}

TEST_F(AtomicWrites, SceneFilesLeaveNothingTruncatedOnAFullDisk) {
  // `spheres` writes a 49 KB PLY (27 spheres) beside its JSON: past the limit.
  const Scene scene = make_builtin_scene("spheres");
  EXPECT_EQ(run_with_a_full_disk([&] { write_scene_file(scene, dir_ / "s.json"); }), 1);
  for (const auto& [name, size] : files()) {
    EXPECT_EQ(name.find(".partial-"), std::string::npos) << name;
    EXPECT_NE(size, kLimitBytes) << name << " was cut at the limit";
    EXPECT_NE(name, "s.json");
  }
  // With room: the JSON and its mesh files, complete.
  EXPECT_EQ(
      run_with_a_full_disk([&] { write_scene_file(make_builtin_scene("quad"), dir_ / "q.json"); }),
      0);
  EXPECT_TRUE(fs::exists(dir_ / "q.json"));
}

}  // namespace
}  // namespace penumbra
