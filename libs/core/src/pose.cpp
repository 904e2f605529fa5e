#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/pose.hpp>

#include "io/text_scanner.hpp"

#include <Eigen/SVD>

#include <cmath>
#include <cstdio>
#include <vector>

namespace icrkit {

namespace {

std::string scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g", value);
  return text;
}

}  // namespace

double orthonormalityError(const Eigen::Matrix3d& m) {
  return (m.transpose() * m - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

bool orthonormaliseReadPose(Eigen::Isometry3d& pose, const std::string& source, const std::string& location,
                            double tolerance) {
  if (!pose.matrix().allFinite()) throw InputError(source, location, "the pose holds a non-finite number");
  const Eigen::Matrix3d r = pose.linear();
  const double error = orthonormalityError(r);
  const double determinant = r.determinant();
  if (!(determinant > 0))
    throw InputError(source, location,
                     "the rotation matrix has determinant " + scientific(determinant) +
                         " (a reflection or a degenerate matrix), expected a rotation");
  if (!(error <= tolerance))
    throw InputError(source, location,
                     "the rotation matrix is not orthonormal: max |R^T R - I| = " + scientific(error) +
                         ", more than the " + scientific(tolerance) +
                         " that rounding of a pose log explains (expected a rotation)");
  if (error <= kExactRotationLevel) return false;
  pose.linear() = nearestRotation(r);
  return true;
}

StampedPose parseTumLine(std::string_view line, const std::string& source, std::size_t line_number, bool* normalised) {
  std::vector<std::string_view> tokens;
  io::detail::splitTokens(line, tokens);
  auto fail = [&](const std::string& detail) {
    throw InputError(source, "line " + std::to_string(line_number), detail);
  };
  if (tokens.size() != 8)
    fail("expected 8 numbers 'timestamp tx ty tz qx qy qz qw', found " + std::to_string(tokens.size()) + " fields");
  double v[8];
  static const char* names[8] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  for (int i = 0; i < 8; ++i)
    if (!io::detail::parseNumber(tokens[i], v[i]) || !std::isfinite(v[i]))
      fail(std::string("expected a finite number for ") + names[i] + ", found '" +
           io::detail::TextScanner::clip(tokens[i]) + "'");
  Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
  const double norm = q.norm();
  // TUM files are written with 4-7 digits; anything further from unit length
  // is a different convention or a corrupted line, not rounding.
  if (!(std::abs(norm - 1.0) <= kReadQuaternionNormTolerance))
    fail("quaternion (qx qy qz qw) has norm " + std::to_string(norm) + ", expected a unit quaternion");
  if (normalised) *normalised = std::abs(norm - 1.0) > kExactRotationLevel;
  q.normalize();
  StampedPose pose;
  pose.timestamp = v[0];
  pose.pose = Eigen::Isometry3d::Identity();
  pose.pose.linear() = q.toRotationMatrix();
  pose.pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
  return pose;
}

std::string formatTumLine(const StampedPose& pose) {
  const Eigen::Quaterniond q(pose.pose.rotation());
  const Eigen::Vector3d& t = pose.pose.translation();
  std::string line;
  const double values[8] = {pose.timestamp, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
  for (int i = 0; i < 8; ++i) {
    if (i > 0) line.push_back(' ');
    io::detail::appendRoundTrip(line, values[i]);
  }
  return line;
}

std::vector<StampedPose> readTumTrajectory(const std::string& path, std::vector<std::uint8_t>* normalised) {
  const std::string text = io::readFileBytes(path);
  io::detail::TextScanner scanner(text, path);
  std::vector<StampedPose> poses;
  if (normalised) normalised->clear();
  while (!scanner.atEnd()) {
    const std::size_t line_number = scanner.line();
    std::string_view line = scanner.restOfLine();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') continue;
    bool changed = false;
    poses.push_back(parseTumLine(line, path, line_number, &changed));
    if (normalised) normalised->push_back(changed ? 1 : 0);
  }
  return poses;
}

void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  writeFileAtomically(
      path,
      [&](std::ostream& out) {
        out << "# timestamp tx ty tz qx qy qz qw\n";
        for (const StampedPose& p : poses) out << formatTumLine(p) << '\n';
      },
      false);
}

}  // namespace icrkit
