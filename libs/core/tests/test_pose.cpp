#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/core/pose_mrpt.hpp>

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

using namespace icrkit;

TEST(Pose, TumLineRoundTripIsExact) {
  StampedPose p;
  p.timestamp = 1305031102.175304;
  p.pose = Eigen::Translation3d(1.3405, 0.6266, 1.6575) *
           Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  const std::string line = formatTumLine(p);
  const StampedPose q = parseTumLine(line, "traj.txt", 1);
  EXPECT_EQ(q.timestamp, p.timestamp);
  EXPECT_EQ(q.pose.translation(), p.pose.translation());
  EXPECT_TRUE(q.pose.linear().isApprox(p.pose.linear(), 1e-15));
}

TEST(Pose, TumLineKnownQuaternion) {
  // 90 degrees about z: x axis goes to y.
  const StampedPose p = parseTumLine("0.5 1 2 3 0 0 0.7071067811865476 0.7071067811865476", "t.txt", 3);
  EXPECT_TRUE((p.pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_EQ(p.pose.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(Pose, TumErrorsNameLineAndField) {
  try {
    parseTumLine("1 2 3", "t.txt", 7);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.txt:line 7"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseTumLine("1 2 3 4 0 0 0 x", "t.txt", 1), InputError);
  EXPECT_THROW(parseTumLine("1 2 3 4 0 0 0 2", "t.txt", 1), InputError);  // not a unit quaternion
  EXPECT_THROW(parseTumLine("1 2 nan 4 0 0 0 1", "t.txt", 1), InputError);
}

TEST(Pose, TumFileWithCommentsRoundTrips) {
  test::ScratchDir dir;
  std::vector<StampedPose> poses(3);
  for (int i = 0; i < 3; ++i) {
    poses[i].timestamp = i * 0.1;
    poses[i].pose = Eigen::Translation3d(i, -i, 0.5 * i) * Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d::UnitY());
  }
  writeTumTrajectory(dir.file("t.txt"), poses);
  const auto back = readTumTrajectory(dir.file("t.txt"));
  ASSERT_EQ(back.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(back[i].pose.isApprox(poses[i].pose, 1e-15));
}

TEST(Pose, MrptConversionMatchesYawPitchRoll) {
  const mrpt::poses::CPose3D mrpt_pose(1.0, -2.0, 0.5, 0.3, -0.2, 0.1);  // x y z yaw pitch roll
  const Eigen::Isometry3d iso = toIsometry(mrpt_pose);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(iso.linear().isApprox(expected, 1e-12));
  EXPECT_EQ(iso.translation(), Eigen::Vector3d(1.0, -2.0, 0.5));

  // Same action on a point and same composition as MRPT's own operators.
  const mrpt::poses::CPose3D other(0.1, 0.2, 0.3, -1.0, 0.4, 2.0);
  const mrpt::poses::CPose3D composed = mrpt_pose + other;
  EXPECT_TRUE(toIsometry(composed).isApprox(iso * toIsometry(other), 1e-12));
  const mrpt::poses::CPose3D back = toCPose3D(iso);
  EXPECT_NEAR(back.yaw(), 0.3, 1e-12);
  EXPECT_NEAR(back.pitch(), -0.2, 1e-12);
  EXPECT_NEAR(back.roll(), 0.1, 1e-12);
  EXPECT_NEAR(back.x(), 1.0, 1e-15);
}
