// Every file of the shared real-sensor data loads, with the documented counts.

#include <icrkit/core/io/geometry_io.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

using namespace icrkit;

TEST(SharedData, EveryGeometryFileLoads) {
  const std::filesystem::path root(ICRKIT_SHARED_DATA_DIR);
  if (!std::filesystem::is_directory(root)) GTEST_SKIP() << "shared test data not found: " << root;
  const std::map<std::string, std::pair<std::size_t, std::size_t>> expected = {
      {"bun_zipper.ply", {35947, 69451}}, {"bun000.ply", {40256, 0}}, {"rubik_cube.obj", {6004, 12004}},
      {"milk.pcd", {13704, 0}}};
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".ply" && ext != ".obj" && ext != ".pcd" && ext != ".xyz")) continue;
    ++files;
    SCOPED_TRACE(entry.path().string());
    TriangleMesh m;
    ASSERT_NO_THROW(m = io::readTriangleMesh(entry.path().string()));
    EXPECT_GT(m.vertexCount(), 0u);
    EXPECT_NO_THROW(m.validate());
    auto it = expected.find(entry.path().filename().string());
    if (it != expected.end()) {
      EXPECT_EQ(m.vertexCount(), it->second.first);
      EXPECT_EQ(m.faceCount(), it->second.second);
    }
  }
  EXPECT_GE(files, 23);
}
