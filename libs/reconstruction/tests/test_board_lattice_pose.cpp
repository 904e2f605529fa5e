// The camera pose from the partly hidden checkerboard of setup B.

#include "simulated_recordings.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/calibration/board_lattice_pose.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <gtest/gtest.h>

#include <cstdio>

namespace icrkit::reconstruction {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

double rotationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

TEST(BoardLatticePose, RecoversTheTrueCameraPoseBehindTheObject) {
  const std::string dir = testing_support::simulatedRecording(12, false, sim::SensorType::Kinect);
  const auto scans = readAllScans(dir + "/scans.rawlog");
  const auto truth = readTumTrajectory(dir + "/ground_truth.txt");
  ASSERT_EQ(scans.size(), truth.size());
  BoardLattice lattice;  // the simulator's plate: 2 cm squares on z = -0.1 mm, lines on multiples of 2 cm
  lattice.origin = Eigen::Vector3d(0, 0, -1e-4);
  std::size_t found = 0;
  double worst_t = 0, worst_r = 0, reported_t = 0, reported_r = 0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const LatticePose pose = latticeCameraPose(scans[i], lattice);
    reported_t = std::max(reported_t, (scans[i].sensor_pose.translation() - truth[i].pose.translation()).norm());
    reported_r = std::max(reported_r, rotationError(scans[i].sensor_pose, truth[i].pose));
    if (!pose.found) continue;
    ++found;
    const Eigen::Vector3d e = truth[i].pose.linear().transpose() * (pose.sensor_pose.translation() - truth[i].pose.translation());
    std::printf("view %zu: %zu corners, rms %.3f px, error (sensor axes) %.2f %.2f %.2f mm, %.3f deg\n", i, pose.corners,
                pose.rms_px, e.x() * 1e3, e.y() * 1e3, e.z() * 1e3, rotationError(pose.sensor_pose, truth[i].pose) / kDeg);
    worst_t = std::max(worst_t, (pose.sensor_pose.translation() - truth[i].pose.translation()).norm());
    worst_r = std::max(worst_r, rotationError(pose.sensor_pose, truth[i].pose));
    EXPECT_GE(pose.corners, 12u);
  }
  std::printf("board poses for %zu of %zu views: worst %.3f mm, %.3f deg (reported poses: %.3f mm, %.3f deg)\n", found,
              scans.size(), worst_t * 1e3, worst_r / kDeg, reported_t * 1e3, reported_r / kDeg);
  // Measured: 11 of 12 views, 15-28 corners at 0.22-0.39 px RMS, worst
  // 5.1 mm / 0.42 deg (rotation and translation trade off over the narrow
  // ring of corners around the object) -- less accurate than this
  // simulator's robot (2.5 mm / 0.22 deg), see docs/calibration.md.
  EXPECT_GE(found, scans.size() * 3 / 4);
  EXPECT_LT(worst_t, 0.006);
  EXPECT_LT(worst_r, 0.5 * kDeg);
}

TEST(BoardLatticePose, NoImageOrBadLattice) {
  RangeScan scan;
  EXPECT_FALSE(latticeCameraPose(scan, BoardLattice{}).found);
  BoardLattice bad;
  bad.square_size = 0.0;
  EXPECT_THROW(latticeCameraPose(scan, bad), InputError);
  bad = BoardLattice{};
  bad.y_axis = Eigen::Vector3d(1, 1, 0);
  EXPECT_THROW(latticeCameraPose(scan, bad), InputError);
}

}  // namespace
}  // namespace icrkit::reconstruction
