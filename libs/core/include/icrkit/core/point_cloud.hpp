#pragma once
/// \file
/// A set of 3D points (metres) with optional normals, colours and named attributes.

#include <icrkit/core/attributes.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace icrkit {

using Colour = std::array<std::uint8_t, 3>;  ///< RGB, 0..255

struct PointCloud {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;  ///< empty, or one unit vector per point
  std::vector<Colour> colours;             ///< empty, or one per point
  AttributeSet attributes;               ///< each holds one value per point

  std::size_t size() const { return positions.size(); }
  bool empty() const { return positions.empty(); }
  bool hasNormals() const { return !normals.empty(); }
  bool hasColours() const { return !colours.empty(); }

  /// A boolean per-point flag stored as a uchar attribute (e.g. "excluded");
  /// a missing attribute reads as false.
  bool flag(const std::string& name, std::size_t index) const;
  /// Sets a flag, creating the uchar attribute (all false) when missing.
  void setFlag(const std::string& name, std::size_t index, bool value);

  /// Resizes positions and every present per-point array (new entries zero).
  void resize(std::size_t count);
  /// Keeps only the listed points, in that order.
  void select(const std::vector<std::size_t>& indices);
  /// Appends another cloud; both must carry the same optional arrays and attributes.
  void append(const PointCloud& other);

  /// Throws std::invalid_argument when array sizes disagree or a coordinate is not finite.
  void validate() const;

  /// Axis-aligned bounds; both are NaN-free only for a non-empty cloud.
  Eigen::AlignedBox3d bounds() const;
};

}  // namespace icrkit
