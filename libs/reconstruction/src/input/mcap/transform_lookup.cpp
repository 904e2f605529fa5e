#include "input/mcap/transform_lookup.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace icrkit::reconstruction::mcap {
namespace {

std::string seconds(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9f", value);
  return text;
}

}  // namespace

std::string tfFrameName(const std::string& frame) {
  return !frame.empty() && frame.front() == '/' ? frame.substr(1) : frame;
}

PoseSample rigidFromRos(const RosTransform& transform, const std::string& source, const std::string& where) {
  for (double v : transform.translation)
    if (!std::isfinite(v)) throw InputError(source, where, "the translation holds a non-finite number");
  for (double v : transform.rotation_xyzw)
    if (!std::isfinite(v)) throw InputError(source, where, "the quaternion holds a non-finite number");
  const auto& r = transform.rotation_xyzw;
  Eigen::Quaterniond q(r[3], r[0], r[1], r[2]);
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= kReadQuaternionNormTolerance))
    throw InputError(source, where,
                     "the quaternion (x y z w) has norm " + std::to_string(norm) + ", expected a unit quaternion");
  PoseSample sample;
  sample.normalised = std::abs(norm - 1.0) > kExactRotationLevel;
  // The very operations of parseTumLine, so that a pose equals the same
  // pose read from a TUM file bit for bit.
  q.normalize();
  sample.pose = Eigen::Isometry3d::Identity();
  sample.pose.linear() = q.toRotationMatrix();
  sample.pose.translation() = Eigen::Vector3d(transform.translation[0], transform.translation[1],
                                              transform.translation[2]);
  return sample;
}

void PoseSeries::add(double stamp, const RosTransform& transform, const std::string& source,
                     const std::string& where) {
  if (!std::isfinite(stamp)) throw InputError(source, where, "the time stamp is not finite");
  const PoseSample checked = rigidFromRos(transform, source, where);
  const auto& r = transform.rotation_xyzw;
  Sample sample;
  sample.stamp = stamp;
  sample.translation = checked.pose.translation();
  sample.rotation = Eigen::Quaterniond(r[3], r[0], r[1], r[2]);
  sample.rotation.normalize();
  sample.normalised = checked.normalised;
  samples_.push_back(sample);
}

void PoseSeries::finish() {
  std::stable_sort(samples_.begin(), samples_.end(),
                   [](const Sample& a, const Sample& b) { return a.stamp < b.stamp; });
}

PoseSample PoseSeries::toPose(const Sample& sample) {
  PoseSample pose;
  pose.pose = Eigen::Isometry3d::Identity();
  pose.pose.linear() = sample.rotation.toRotationMatrix();
  pose.pose.translation() = sample.translation;
  pose.normalised = sample.normalised;
  return pose;
}

std::optional<PoseSample> PoseSeries::at(double stamp, double max_time_difference, double& nearest) const {
  nearest = 0.0;
  if (samples_.empty()) return std::nullopt;
  const auto after = std::lower_bound(samples_.begin(), samples_.end(), stamp,
                                      [](const Sample& s, double t) { return s.stamp < t; });
  if (after != samples_.end() && after->stamp == stamp) return toPose(*after);
  if (after == samples_.begin() || after == samples_.end()) {
    const Sample& only = after == samples_.end() ? samples_.back() : *after;
    nearest = only.stamp;
    if (std::abs(only.stamp - stamp) <= max_time_difference) return toPose(only);
    return std::nullopt;
  }
  const Sample& a = *(after - 1);
  const Sample& b = *after;
  nearest = stamp - a.stamp <= b.stamp - stamp ? a.stamp : b.stamp;
  if (!(std::abs(nearest - stamp) <= max_time_difference)) return std::nullopt;
  const double s = (stamp - a.stamp) / (b.stamp - a.stamp);
  PoseSample pose;
  pose.pose = Eigen::Isometry3d::Identity();
  pose.pose.linear() = a.rotation.slerp(s, b.rotation).normalized().toRotationMatrix();
  pose.pose.translation() = a.translation + s * (b.translation - a.translation);
  pose.normalised = a.normalised || b.normalised;
  return pose;
}

void TransformTree::add(const RosTransformStamped& transform, bool is_static, const std::string& source,
                        const std::string& where) {
  const std::string parent = tfFrameName(transform.header.frame_id);
  const std::string child = tfFrameName(transform.child_frame_id);
  if (parent.empty() || child.empty() || parent == child)
    throw InputError(source, where,
                     "expected a transform between two different named frames, found '" + parent + "' -> '" + child +
                         "'");
  auto [it, inserted] = edges_.try_emplace(child);
  Edge& edge = it->second;
  if (inserted) {
    edge.parent = parent;
    edge.is_static = is_static;
  } else if (edge.parent != parent || edge.is_static != is_static) {
    throw InputError(source, where,
                     "frame '" + child + "' has two parents or is both static and dynamic ('" + edge.parent +
                         "' in " + (edge.is_static ? "/tf_static" : "/tf") + ", '" + parent + "' in " +
                         (is_static ? "/tf_static" : "/tf") + "); tf needs a tree");
  }
  // A static transform holds at any time; a later one replaces it (latched
  // republishing).
  if (is_static) edge.series = PoseSeries();
  edge.series.add(is_static ? 0.0 : transform.header.stamp.seconds(), transform.transform, source, where);
}

void TransformTree::finish() {
  for (auto& [child, edge] : edges_) edge.series.finish();
}

bool TransformTree::hasFrame(const std::string& frame) const {
  const std::string name = tfFrameName(frame);
  if (edges_.count(name) > 0) return true;
  for (const auto& [child, edge] : edges_)
    if (edge.parent == name) return true;
  return false;
}

std::vector<std::string> TransformTree::pathToRoot(const std::string& frame) const {
  std::vector<std::string> path{frame};
  // Every frame has at most one parent; a chain longer than the edge count is a cycle.
  while (path.size() <= edges_.size() + 1) {
    const auto it = edges_.find(path.back());
    if (it == edges_.end()) return path;
    path.push_back(it->second.parent);
  }
  path.push_back({});  // marks the cycle
  return path;
}

PoseSample TransformTree::lookup(const std::string& parent_frame, const std::string& child_frame, double stamp,
                                 double max_time_difference, const std::string& source,
                                 const std::string& location) const {
  const std::string parent = tfFrameName(parent_frame), child = tfFrameName(child_frame);
  const std::string frames = "tf '" + parent + "' -> '" + child + "'";
  if (parent == child) return PoseSample{};
  const std::vector<std::string> up_from_child = pathToRoot(child);
  const std::vector<std::string> up_from_parent = pathToRoot(parent);
  if (up_from_child.back().empty() || up_from_parent.back().empty())
    throw InputError(source, location, frames + ": the tf frames form a cycle");
  std::size_t in_child = 0, in_parent = 0;
  bool found = false;
  for (; in_child < up_from_child.size() && !found; ++in_child) {
    const auto it = std::find(up_from_parent.begin(), up_from_parent.end(), up_from_child[in_child]);
    if (it != up_from_parent.end()) {
      in_parent = static_cast<std::size_t>(it - up_from_parent.begin());
      found = true;
      break;
    }
  }
  if (!found)
    throw InputError(source, location,
                     frames + ": no chain of transforms in /tf and /tf_static joins the two frames (" + child +
                         " leads up to '" + up_from_child.back() + "', " + parent + " to '" +
                         up_from_parent.back() + "')");

  bool normalised = false;
  // The pose of path[0] in path[depth], composed from the ancestor down.
  auto chain = [&](const std::vector<std::string>& path, std::size_t depth) {
    std::optional<Eigen::Isometry3d> pose;
    for (std::size_t i = depth; i-- > 0;) {
      const Edge& edge = edges_.at(path[i]);
      double nearest = 0.0;
      const std::optional<PoseSample> sample =
          edge.is_static ? edge.series.at(0.0, 0.0, nearest) : edge.series.at(stamp, max_time_difference, nearest);
      if (!sample)
        throw InputError(source, location,
                         frames + ": the transform '" + edge.parent + "' -> '" + path[i] +
                             "' has no message within " + seconds(max_time_difference) + " s of the image at " +
                             seconds(stamp) + " (nearest: " + seconds(nearest) + ")");
      normalised = normalised || sample->normalised;
      // The first edge as it is, so that a one-edge chain (or one composed
      // with identities) equals the message exactly.
      pose = pose ? Eigen::Isometry3d(*pose * sample->pose) : sample->pose;
    }
    return pose;
  };
  const std::optional<Eigen::Isometry3d> ancestor_to_child = chain(up_from_child, in_child);
  const std::optional<Eigen::Isometry3d> ancestor_to_parent = chain(up_from_parent, in_parent);
  PoseSample result;
  result.normalised = normalised;
  const Eigen::Isometry3d child_in_ancestor = ancestor_to_child.value_or(Eigen::Isometry3d::Identity());
  result.pose = ancestor_to_parent ? Eigen::Isometry3d(ancestor_to_parent->inverse() * child_in_ancestor)
                                   : child_in_ancestor;
  return result;
}

}  // namespace icrkit::reconstruction::mcap
