// The direct OFF reader (scene/off_reader.hpp) must give exactly the mesh of the assimp import
// (scene/mesh_loader.hpp): the same floats, bit for bit, in the same order, and the same
// triangles. Checked on the scanned models when they are fetched (scripts/fetch-models.sh) and on
// small files written here for each rule it copies (number forms, joined and unused vertices,
// negative zeros, line endings); files outside its subset must be left to assimp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>

#include "penumbra/scene/mesh_header.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/off_reader.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return std::move(text).str();
}

/// Both readers on `path`: the direct one must accept it, and agree with assimp bit for bit.
void expect_same_as_assimp(const fs::path& path) {
  SCOPED_TRACE(path.string());
  const std::string bytes = read_bytes(path);
  const std::optional<MeshFileCounts> counts = validate_mesh_file(bytes, ".off");
  ASSERT_TRUE(counts);
  const std::optional<Mesh> direct = read_plain_off(bytes, path.stem().string());
  ASSERT_TRUE(direct) << "outside the direct reader's subset";
  const Mesh assimp = import_mesh_file(path, counts);
  EXPECT_EQ(direct->name, assimp.name);
  ASSERT_EQ(direct->positions.size(), assimp.positions.size());
  EXPECT_EQ(std::memcmp(direct->positions.data(), assimp.positions.data(),
                        assimp.positions.size() * sizeof(Vec3)),
            0);
  ASSERT_EQ(direct->triangles.size(), assimp.triangles.size());
  EXPECT_EQ(std::memcmp(direct->triangles.data(), assimp.triangles.data(),
                        assimp.triangles.size() * sizeof(Triangle)),
            0);
  EXPECT_TRUE(assimp.normals.empty());
  EXPECT_TRUE(assimp.uvs.empty());
  // And load_mesh_file takes the direct path to the same mesh.
  const Mesh loaded = load_mesh_file(path);
  EXPECT_EQ(loaded.positions.size(), assimp.positions.size());
}

class OffReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("penumbra_off_reader_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  fs::path dir_;
};

TEST(OffReader, ScannedModelsEqualAssimp) {
  int found = 0;
  for (const char* name : {"bunny00.off", "ChineseDragon-10kv.off", "armadillo.off",
                           "refined_elephant.off", "Wuson.off"})
    if (const std::optional<fs::path> path = find_model(name)) {
      ++found;
      expect_same_as_assimp(*path);
    }
  if (found == 0) GTEST_SKIP() << "no OFF model fetched: run scripts/fetch-models.sh";
}

TEST_F(OffReaderTest, NumberFormsEqualAssimp) {
  // Integer parts, fractions longer than the 15 digits assimp reads, trailing and leading dots,
  // signs, values whose float sum of parts differs from the correctly rounded decimal.
  expect_same_as_assimp(write("numbers.off",
                              "OFF\n"
                              "6 4 0\n"
                              "0.1234567890123456789 -12345.6789 +3.\n"
                              "-.25 16777217.5 0.3333333333333333\n"
                              "1 2 3\n"
                              "  -0.000001\t7.000001   99999.99999\n"
                              "0.1 0.2 0.3\n"
                              "123456789.987654321 -8.84815e-005 2.5E+3\n"
                              "3 0 1 2\n"
                              "3 2 3 4\n"
                              "3 4 5 0\n"
                              "3 1 3 5\n"));
}

TEST_F(OffReaderTest, JoinsEqualPositionsDropsUnusedAndPositiveZeros) {
  // Vertex 3 repeats vertex 0, vertex 4 is −0 where vertex 1 is +0 (equal: joined), vertex 2 is
  // never used, vertex 6 is −0 alone (comes out +0); CRLF endings and blank lines between.
  const fs::path path = write("join.off",
                              "OFF\r\n"
                              "7 4 0\r\n"
                              "\r\n"
                              "1 0 0\r\n"
                              "0 0 1\r\n"
                              "5 5 5\r\n"
                              "\r\n"
                              "1 0 0\r\n"
                              "-0 0 1\r\n"
                              "0 1 0\r\n"
                              "-0 -0.0 2\r\n"
                              "3 0 1 5\r\n"
                              "3 3 5 4\r\n"
                              "\r\n"
                              "3 5 6 0\r\n"
                              "3 1 4 6\r\n");
  expect_same_as_assimp(path);
  const std::optional<Mesh> mesh = read_plain_off(read_bytes(path), "join");
  ASSERT_TRUE(mesh);
  ASSERT_EQ(mesh->positions.size(), 4u);  // 0 (= 3), 1 (= 4), 5, 6
  EXPECT_FALSE(std::signbit(mesh->positions[3].x));
  EXPECT_EQ(mesh->triangles[1].v[0], 0u);
  EXPECT_EQ(mesh->triangles[1].v[2], 1u);
}

TEST_F(OffReaderTest, FilesOutsideTheSubsetGoToAssimp) {
  const std::string tri = "3 0 1 2\n";
  const std::string three = "0 0 0\n1 0 0\n0 1 0\n";
  for (const std::string& text : std::initializer_list<std::string>{
           "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n",        // a quad
           "OFF\n3 1 0\n# comment\n" + three + tri,                      // a comment line
           "OFF\n3 1 0\n0 0 0\ninf 0 0\n0 1 0\n" + tri,                  // not a number
           "OFF\n3 1 0\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 1 1 1\n" + tri,  // colours
           "COFF\n3 1 0\n" + three + tri,                                // another header
           "OFF 3 1 0\n" + three + tri,                                  // counts on its line
           "OFF\n3 1 0\n" + three + "   \n" + tri,                       // a line of blanks
           "OFF\n3 1 0\n0 0 0\n0.0000000000001 0 0\n0 1 0\n" + tri,      // below 1e-12
           // And what the validation refuses: an index past the vertices, a missing face, a
           // header counting more vertices than the file holds, a huge coordinate.
           "OFF\n3 1 0\n" + three + "3 0 1 3\n", "OFF\n3 2 0\n" + three + tri,
           "OFF\n4 1 0\n" + three + tri,
           "OFF\n4000000000 1 0\n" + three + tri,  // refused before allocating 48 GB
           "OFF\n3 1 0\n0 0 0\n1e39 0 0\n0 1 0\n" + tri,
           "OFF\n3 1 0\n0 0 0\n1e-999 0 0\n0 1 0\n" + tri,  // the validation refuses it
       }) {
    SCOPED_TRACE(text);
    EXPECT_FALSE(read_plain_off(text, "x"));
  }
  // A quad file still loads, through assimp.
  const fs::path quad = write("quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  EXPECT_EQ(load_mesh_file(quad).triangles.size(), 2u);
}

/// Assimp's OFF importer drops faces of more than 9 indices (a decagon loaded as "no faces"):
/// such files go to its OBJ importer as the same polygons, triangulated as OBJ n-gons are.
TEST_F(OffReaderTest, PolygonsOfTenOrMoreVerticesLoadAsObjNgonsDo) {
  for (const int n : {10, 50, 1000}) {
    SCOPED_TRACE(n);
    std::ostringstream off, obj;
    off << "COFF\n# a regular " << n << "-gon and a triangle, with colours\n" << n + 3 << " 2 0\n";
    for (int i = 0; i < n; ++i) {
      const double angle = 2.0 * 3.14159265358979 * i / n;
      off << 0.5 * std::cos(angle) << " 0.5 " << 0.5 * std::sin(angle) << " 1 0 0 1\n";
      obj << "v " << 0.5 * std::cos(angle) << " 0.5 " << 0.5 * std::sin(angle) << "\n";
    }
    off << "0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 0 1 1 0 0 1\n" << n;
    obj << "v 0 0 0\nv 1 0 0\nv 0 0 1\nf";
    for (int i = 0; i < n; ++i) {
      off << ' ' << i;
      obj << ' ' << i + 1;
    }
    off << "\n3 " << n << ' ' << n + 1 << ' ' << n + 2 << "\n";
    obj << "\nf " << n + 1 << ' ' << n + 2 << ' ' << n + 3 << "\n";
    const Mesh from_off = load_mesh_file(write("polygon.off", off.str()));
    const Mesh from_obj = load_mesh_file(write("polygon.obj", obj.str()));
    ASSERT_EQ(from_off.triangles.size(), static_cast<size_t>(n - 2 + 1));
    ASSERT_EQ(from_off.positions.size(), from_obj.positions.size());
    EXPECT_EQ(std::memcmp(from_off.positions.data(), from_obj.positions.data(),
                          from_obj.positions.size() * sizeof(Vec3)),
              0);
    ASSERT_EQ(from_off.triangles.size(), from_obj.triangles.size());
    EXPECT_EQ(std::memcmp(from_off.triangles.data(), from_obj.triangles.data(),
                          from_obj.triangles.size() * sizeof(Triangle)),
              0);
    // The triangulation covers the polygon: its area, n/2 · r² · sin(2π/n), plus the triangle's.
    double area = 0.0;
    for (const Triangle& t : from_off.triangles) {
      const Vec3 a = from_off.positions[t.v[0]], b = from_off.positions[t.v[1]],
                 c = from_off.positions[t.v[2]];
      area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    const double expected = n / 2.0 * 0.25 * std::sin(2.0 * 3.14159265358979 / n) + 0.5;
    EXPECT_NEAR(area, expected, 1e-5);
  }
  // The reproducer's decagon alone (assimp: "Mesh contains no faces").
  const fs::path decagon = write("decagon.off",
                                 "OFF\n10 1 0\n0.5 0.5 0.0\n0.4045 0.5 0.2939\n0.1545 0.5 0.4755\n"
                                 "-0.1545 0.5 0.4755\n-0.4045 0.5 0.2939\n-0.5 0.5 0\n"
                                 "-0.4045 0.5 -0.2939\n-0.1545 0.5 -0.4755\n0.1545 0.5 -0.4755\n"
                                 "0.4045 0.5 -0.2939\n10 0 1 2 3 4 5 6 7 8 9\n");
  EXPECT_EQ(load_mesh_file(decagon).triangles.size(), 8u);
  EXPECT_FALSE(off_polygons_as_obj("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"));
}

/// 400 one-character mutations of a small plain file: whenever the direct reader accepts one, the
/// validation must accept it too and assimp must read the same mesh.
TEST_F(OffReaderTest, MutatedFilesAgreeWithTheValidationAndAssimp) {
  const std::string base =
      "OFF\n5 3 0\n0.5 -1.25 3\n-0 2.000001 1e-3\n4 4.5 -0.75\n1 0 0\n0 1 0\n"
      "3 0 1 2\n3 2 3 4\n3 4 0 1\n";
  const std::string alphabet = " 0123456789.-+eE\n#x";
  uint32_t state = 2024;
  const auto next = [&](uint32_t n) {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) % n;
  };
  int accepted = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::string text = base;
    const size_t at = next(static_cast<uint32_t>(text.size()));
    const char c = alphabet[next(static_cast<uint32_t>(alphabet.size()))];
    switch (next(3)) {
      case 0:
        text[at] = c;
        break;
      case 1:
        text.insert(text.begin() + static_cast<long>(at), c);
        break;
      default:
        text.erase(at, 1);
    }
    if (!read_plain_off(text, "m")) continue;
    ++accepted;
    SCOPED_TRACE(text);
    const fs::path path = write("m.off", text);
    EXPECT_NO_THROW(validate_mesh_file(text, ".off"));
    expect_same_as_assimp(path);
  }
  EXPECT_GT(accepted, 40);  // the mutations that keep a plain file (digits for digits, ...)
}

}  // namespace
}  // namespace penumbra
