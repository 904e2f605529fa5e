#pragma once
/// \file
/// Rigid poses and TUM trajectory files (`timestamp tx ty tz qx qy qz qw`),
/// and the repair of rotations read from files (docs/rawlog.md, "Poses as
/// read").

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace icrkit {

struct StampedPose {
  double timestamp = 0.0;  ///< seconds
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// Largest entry of |R^T R - I| accepted in a rotation matrix read from a
/// file; such a matrix is replaced by its nearest rotation (and counted).
/// Pose logs written with 7 significant digits are off by about 1e-6, but
/// real recordings go further: the sensorPose matrices of the real
/// PrimeSense bunny rawlog (../shared/data/primesense-bunny) are off by
/// 6e-3 to 8.5e-3 (column norms 0.9957-0.9999), a rotation re-estimated and
/// stored without re-orthonormalising. 0.02 accepts those with a margin;
/// a scaled matrix (a unit mix-up), a swapped or mirrored axis, a shear or
/// a corrupted record is off by 0.1 or more and refused.
inline constexpr double kReadRotationTolerance = 0.02;
/// Largest |norm - 1| accepted in a quaternion read from a file (TUM files
/// are written with 4 to 9 digits).
inline constexpr double kReadQuaternionNormTolerance = 1e-3;
/// Deviations up to this (of |R^T R - I| or of a quaternion's norm) are
/// double rounding: such rotations are used as they are and not counted.
inline constexpr double kExactRotationLevel = 1e-12;

/// max |(m^T m - I)_ij|.
double orthonormalityError(const Eigen::Matrix3d& m);
/// The rotation nearest to `m` in the Frobenius norm: the orthogonal polar
/// factor U V^T of m's SVD (m must have a positive determinant).
Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& m);
/// Checks the rotation of a pose read from a file. Within `tolerance`
/// (orthonormalityError, determinant > 0) it is replaced by
/// nearestRotation() unless it is already exact to kExactRotationLevel;
/// returns whether it was replaced. Beyond it, or with a non-finite number
/// in the pose, throws InputError(source, location, ...).
bool orthonormaliseReadPose(Eigen::Isometry3d& pose, const std::string& source, const std::string& location,
                            double tolerance = kReadRotationTolerance);

/// Parses one TUM line; `source` and `line_number` name it in the InputError
/// thrown on a malformed line or a quaternion further than
/// kReadQuaternionNormTolerance from unit length. The quaternion is
/// normalised; `normalised`, when given, says whether its norm was off by
/// more than kExactRotationLevel.
StampedPose parseTumLine(std::string_view line, const std::string& source, std::size_t line_number,
                         bool* normalised = nullptr);
/// Formats one TUM line with round-trip precision (no trailing newline).
std::string formatTumLine(const StampedPose& pose);

/// Reads a TUM trajectory; '#' comments and blank lines are skipped.
/// `normalised`, when given, gets one flag per pose (parseTumLine's).
std::vector<StampedPose> readTumTrajectory(const std::string& path, std::vector<std::uint8_t>* normalised = nullptr);
/// Writes a TUM trajectory atomically.
void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);

}  // namespace icrkit
