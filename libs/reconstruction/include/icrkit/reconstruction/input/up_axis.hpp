#pragma once
/// \file
/// The object frame's up axis, read from the sensors' poses: the side a
/// standing object rests on, where the support-plane filter looks for the
/// table. A robot's base frame has +z up; a frame taken from a model often
/// has not (the Stanford bunny's, and so the shared PrimeSense recording's,
/// has +y up), and a filter that assumed +z there cut the bunny's ears and
/// flanks as "table" while the real table stayed (docs/reconstruction.md).

#include <Eigen/Geometry>

#include <vector>

namespace icrkit::reconstruction {

/// Cameras look at a standing object upright, from level or from above: each
/// sensor's up axis minus its optical axis (MRPT axes: +z minus +x) lies
/// within 45 deg of the world's up whatever its elevation (0-90 deg), and
/// over views from around the object the horizontal parts cancel.
///
/// Returns +z when the sum of those vectors is within `z_preference` of +z
/// (radians; default 60 deg: a robot's frame is kept even when all views
/// come from one side), otherwise the object-frame axis (+-x, +-y, +-z)
/// nearest it (a model's frame is axis-aligned with its up), and +z when the
/// sum vanishes or there are no poses.
Eigen::Vector3d estimateUpAxis(const std::vector<Eigen::Isometry3d>& sensor_poses,
                               double z_preference = 1.0471975511965976);

}  // namespace icrkit::reconstruction
