#pragma once
/// \file
/// Rigid poses and TUM trajectory files (`timestamp tx ty tz qx qy qz qw`).

#include <Eigen/Geometry>

#include <string>
#include <string_view>
#include <vector>

namespace icrkit {

struct StampedPose {
  double timestamp = 0.0;  ///< seconds
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// Parses one TUM line; `source` and `line_number` name it in the InputError
/// thrown on a malformed line or a quaternion far from unit length.
StampedPose parseTumLine(std::string_view line, const std::string& source, std::size_t line_number);
/// Formats one TUM line with round-trip precision (no trailing newline).
std::string formatTumLine(const StampedPose& pose);

/// Reads a TUM trajectory; '#' comments and blank lines are skipped.
std::vector<StampedPose> readTumTrajectory(const std::string& path);
/// Writes a TUM trajectory atomically.
void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);

}  // namespace icrkit
