#pragma once
/// \file
/// Poses at an image's time stamp from stamped messages: one series (a
/// PoseStamped topic, one tf edge) interpolated between the two messages
/// around the stamp, and chains of tf edges composed from one frame to another.

#include "input/mcap/ros_messages.hpp"

#include <Eigen/Geometry>

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction::mcap {

/// A pose and whether its quaternion had to be normalised when read.
struct PoseSample {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  bool normalised = false;
};

/// The rigid transform of a ROS translation and quaternion, made exactly as
/// a TUM line is read (parseTumLine): the quaternion is normalised, and one
/// further than kReadQuaternionNormTolerance from unit length, or a
/// non-finite number, is InputError(source, where, ...).
PoseSample rigidFromRos(const RosTransform& transform, const std::string& source, const std::string& where);

/// Stamped poses of one source, looked up at any time.
class PoseSeries {
 public:
  void add(double stamp, const RosTransform& transform, const std::string& source, const std::string& where);
  /// Sorts by stamp (messages of equal stamps keep their file order).
  void finish();
  bool empty() const { return samples_.empty(); }
  std::size_t size() const { return samples_.size(); }

  /// The pose at `stamp`: a message at exactly that stamp as it is; between
  /// two messages, translation interpolated linearly and rotation by slerp,
  /// when the nearer of the two lies within `max_time_difference`; before
  /// the first or after the last message, the nearest one when within
  /// `max_time_difference`. Nothing otherwise, with `nearest` set to the
  /// stamp of the nearest message.
  std::optional<PoseSample> at(double stamp, double max_time_difference, double& nearest) const;

 private:
  struct Sample {
    double stamp = 0.0;
    Eigen::Vector3d translation;
    Eigen::Quaterniond rotation;
    bool normalised = false;
  };
  static PoseSample toPose(const Sample& sample);
  std::vector<Sample> samples_;
};

/// The tf tree of /tf (stamped edges) and /tf_static (edges valid at any time).
class TransformTree {
 public:
  /// Frame ids are taken without a leading '/' (tf2 ignores it too).
  void add(const RosTransformStamped& transform, bool is_static, const std::string& source, const std::string& where);
  void finish();
  bool hasFrame(const std::string& frame) const;

  /// The pose of `child` in `parent` at `stamp`, each dynamic edge of the
  /// chain between them looked up as PoseSeries::at does. Throws
  /// InputError(source, location, ...) naming the frames, or the edge that
  /// has no transform near the stamp.
  PoseSample lookup(const std::string& parent, const std::string& child, double stamp, double max_time_difference,
                    const std::string& source, const std::string& location) const;

 private:
  struct Edge {
    std::string parent;
    bool is_static = false;
    PoseSeries series;  // a static edge holds its latest message only
  };
  std::vector<std::string> pathToRoot(const std::string& frame) const;
  std::map<std::string, Edge> edges_;  // by child frame
};

/// `frame` without a leading '/'.
std::string tfFrameName(const std::string& frame);

}  // namespace icrkit::reconstruction::mcap
