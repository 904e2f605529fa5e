#pragma once
// Helpers shared by every library's tests (icrkit_add_test puts this folder
// on each test binary's include path): shared-data paths, file reading, a
// scratch folder, a unit cube, and the InputError a call throws.

#include <icrkit/core/error.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace icrkit::test {

/// Path of a file in the shared real-data directory.
inline std::string sharedData(const std::string& relative) {
  return std::string(ICRKIT_SHARED_DATA_DIR) + "/" + relative;
}

/// The whole content of a file ("" when it cannot be read).
inline std::string readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Unit cube [0,1]^3 (shifted), outward winding. Each side is a quad
/// (a,b,c,d) split along its a-c diagonal into faces 2q (a,b,c) and 2q+1
/// (a,c,d), in the order -x, +x, -y, +y, -z, +z.
inline TriangleMesh unitCube(const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.positions.push_back(Eigen::Vector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1) + shift);
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    mesh.faces.emplace_back(q[0], q[1], q[2]);
    mesh.faces.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

/// A fresh scratch directory, removed with the object.
class ScratchDir {
public:
  ScratchDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("icrkit_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

private:
  std::filesystem::path path_;
};

/// Runs `f` and returns the InputError it threw; records a failure (and
/// returns an empty error) when it threw none.
template <typename Function>
InputError expectInputError(Function&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", "", "");
}

}  // namespace icrkit::test

/// Skips the current test when a shared data file is absent.
#define ICRKIT_REQUIRE_SHARED_FILE(path)                                                          \
  do {                                                                                            \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared test data not found: " << (path); \
  } while (0)
