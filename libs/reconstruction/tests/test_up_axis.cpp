/// \file
/// The object frame's up axis from the sensors' poses: camera rings and
/// one-sided view sets in z-up and y-up frames, and the real recording's
/// poses (bun_zipper's frame, y up).


#include <icrkit/reconstruction/input/up_axis.hpp>

#include <icrkit/core/pose.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace icrkit::reconstruction {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The sensor pose (MRPT axes: x forward, z up, no roll) of a camera at
// `azimuth`, looking down at the origin by `elevation`, in a z-up world.
Eigen::Isometry3d cameraAt(double azimuth, double elevation, double distance = 0.6) {
  const Eigen::Vector3d eye = distance * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                                                         std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
  const Eigen::Vector3d forward = -eye.normalized();
  const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << forward, left, forward.cross(left);
  pose.translation() = eye;
  return pose;
}

std::vector<Eigen::Isometry3d> ring(int count, double elevation, double first = 0.0, double span = 2.0 * M_PI) {
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < count; ++k) poses.push_back(cameraAt(first + span * k / count, elevation));
  return poses;
}

// The same views in a frame whose +y is the world's up (a model's frame).
std::vector<Eigen::Isometry3d> inYUpFrame(std::vector<Eigen::Isometry3d> poses) {
  const Eigen::Isometry3d z_to_y(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  for (Eigen::Isometry3d& p : poses) p = z_to_y * p;
  return poses;
}

TEST(UpAxis, CameraRingsGiveTheWorldsUp) {
  for (double elevation : {0.0, 20 * kDeg, 45 * kDeg, 70 * kDeg, 89 * kDeg}) {
    EXPECT_EQ(estimateUpAxis(ring(12, elevation)), Eigen::Vector3d::UnitZ()) << elevation / kDeg;
    EXPECT_EQ(estimateUpAxis(inYUpFrame(ring(12, elevation))), Eigen::Vector3d::UnitY()) << elevation / kDeg;
  }
}

TEST(UpAxis, ViewsFromOneSide) {
  // A quarter turn seen from 0-80 deg above: the horizontal parts do not
  // cancel, yet each view's up minus forward stays within 45 deg of up.
  for (double elevation : {0.0, 30 * kDeg, 60 * kDeg, 80 * kDeg}) {
    const auto poses = ring(5, elevation, 0.3, M_PI / 2);
    EXPECT_EQ(estimateUpAxis(poses), Eigen::Vector3d::UnitZ()) << elevation / kDeg;
    EXPECT_EQ(estimateUpAxis(inYUpFrame(poses)), Eigen::Vector3d::UnitY()) << elevation / kDeg;
    EXPECT_EQ(estimateUpAxis({poses.front()}), Eigen::Vector3d::UnitZ()) << elevation / kDeg;
  }
  // A frame with -x up.
  const Eigen::Isometry3d z_to_minus_x(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()));
  std::vector<Eigen::Isometry3d> poses = ring(8, 30 * kDeg);
  for (Eigen::Isometry3d& p : poses) p = z_to_minus_x * p;
  EXPECT_EQ(estimateUpAxis(poses), -Eigen::Vector3d::UnitX());
}

TEST(UpAxis, NothingToReadGivesZ) {
  EXPECT_EQ(estimateUpAxis({}), Eigen::Vector3d::UnitZ());
  // Two views upside down against each other cancel.
  Eigen::Isometry3d a = cameraAt(0.0, 0.0), b = a;
  b.linear() = a.linear() * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  // b's forward is -a's forward and its up -a's up: the sum vanishes.
  EXPECT_EQ(estimateUpAxis({a, b}), Eigen::Vector3d::UnitZ());
}

TEST(UpAxis, RealRecordingIsYUp) {
  const std::string dir = std::string(ICRKIT_SHARED_DATA_DIR) + "/primesense-bunny";
  if (!std::filesystem::exists(dir + "/reported_poses.txt")) GTEST_SKIP() << "shared test data not found: " << dir;
  // bun_zipper's frame: the table is y = 0.033 m, the ears reach y = 0.187.
  for (const char* file : {"/reported_poses.txt", "/ground_truth.txt"}) {
    std::vector<Eigen::Isometry3d> poses;
    for (const StampedPose& p : readTumTrajectory(dir + file)) poses.push_back(p.pose);
    EXPECT_EQ(estimateUpAxis(poses), Eigen::Vector3d::UnitY()) << file;
  }
}

}  // namespace
}  // namespace icrkit::reconstruction
