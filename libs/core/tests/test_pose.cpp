#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/core/pose_mrpt.hpp>

#include <test_support.hpp>

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

namespace {

// A rotation with its entries disturbed by up to `amount` (a fixed,
// non-symmetric pattern, as rounding of a written matrix would do).
Eigen::Isometry3d disturbedPose(double amount) {
  Eigen::Isometry3d pose =
      Eigen::Translation3d(0.1, -0.2, 0.7) * Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1.0, 0.4).normalized());
  Eigen::Matrix3d noise;
  noise << 0.4, -0.9, 0.2,  //
      -0.3, 0.7, 1.0,       //
      0.8, -0.1, -0.6;
  pose.linear() += amount * noise;
  return pose;
}

}  // namespace

TEST(Pose, RotationJustInsideTheToleranceIsProjected) {
  Eigen::Isometry3d pose = disturbedPose(5e-6);
  const Eigen::Matrix3d before = pose.linear();
  ASSERT_GT(orthonormalityError(before), 1e-6);
  ASSERT_LT(orthonormalityError(before), kReadRotationTolerance);
  EXPECT_TRUE(orthonormaliseReadPose(pose, "poses.txt", "scan 3"));
  EXPECT_LE(orthonormalityError(pose.linear()), 1e-12);
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
  // The nearest rotation: the change is of the size of the disturbance.
  EXPECT_LT((pose.linear() - before).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_EQ(pose.translation(), Eigen::Vector3d(0.1, -0.2, 0.7));
  // Polar factor: (R^T M) is symmetric positive definite.
  const Eigen::Matrix3d s = pose.linear().transpose() * before;
  EXPECT_LT((s - s.transpose()).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(Pose, RotationAsFarOffAsTheRealBunnyRawlogIsProjected) {
  // The real PrimeSense rawlog's sensorPose matrices are off by up to 8.5e-3.
  Eigen::Isometry3d pose = disturbedPose(0.007);
  ASSERT_GT(orthonormalityError(pose.linear()), 0.005);
  ASSERT_LT(orthonormalityError(pose.linear()), kReadRotationTolerance);
  EXPECT_TRUE(orthonormaliseReadPose(pose, "scans.rawlog", "scan 0"));
  EXPECT_LE(orthonormalityError(pose.linear()), 1e-12);
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
}

TEST(Pose, ExactRotationIsLeftAlone) {
  Eigen::Isometry3d pose = disturbedPose(0.0);
  const Eigen::Isometry3d before = pose;
  EXPECT_FALSE(orthonormaliseReadPose(pose, "poses.txt", "scan 0"));
  EXPECT_EQ(pose.matrix(), before.matrix());
}

TEST(Pose, RotationBeyondTheToleranceNamesTheScan) {
  Eigen::Isometry3d pose = disturbedPose(0.03);
  ASSERT_GT(orthonormalityError(pose.linear()), kReadRotationTolerance);
  try {
    orthonormaliseReadPose(pose, "rec.rawlog", "scan 7");
    FAIL() << "accepted a matrix 0.03 from a rotation";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "rec.rawlog");
    EXPECT_EQ(e.location(), "scan 7");
    EXPECT_NE(e.detail().find("not orthonormal"), std::string::npos) << e.what();
  }
  Eigen::Isometry3d mirrored = disturbedPose(0.0);
  mirrored.linear().col(0) *= -1.0;
  EXPECT_THROW(orthonormaliseReadPose(mirrored, "rec.rawlog", "scan 1"), InputError);
  Eigen::Isometry3d broken = disturbedPose(0.0);
  broken.translation().x() = std::nan("");
  EXPECT_THROW(orthonormaliseReadPose(broken, "rec.rawlog", "scan 2"), InputError);
}

TEST(Pose, NearestRotationOfARotationIsItself) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  EXPECT_TRUE(nearestRotation(r).isApprox(r, 1e-15));
  EXPECT_TRUE(nearestRotation(1.001 * r).isApprox(r, 1e-14));
}

TEST(Pose, TumQuaternionOffUnitLengthIsNormalisedAndFlagged) {
  bool normalised = false;
  // 90 degrees about z with a norm of 0.9999.
  const double c = 0.9999 * std::sqrt(0.5);
  const std::string line = "2 0 0 0 0 0 " + std::to_string(c) + " " + std::to_string(c);
  const StampedPose p = parseTumLine(line, "t.txt", 4, &normalised);
  EXPECT_TRUE(normalised);
  EXPECT_LE(orthonormalityError(p.pose.linear()), 1e-15);
  EXPECT_TRUE((p.pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  parseTumLine("0.5 1 2 3 0 0 0 1", "t.txt", 3, &normalised);
  EXPECT_FALSE(normalised);

  test::ScratchDir dir;
  {
    std::ofstream out(dir.file("q.txt"));
    out << "# comment\n1 0 0 0 0 0 0 1\n" << line << "\n";
  }
  std::vector<std::uint8_t> flags;
  const auto poses = readTumTrajectory(dir.file("q.txt"), &flags);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(flags, (std::vector<std::uint8_t>{0, 1}));
}
