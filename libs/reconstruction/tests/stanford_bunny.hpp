#pragma once
/// \file
/// The Stanford bunny's range scans (../shared/data/stanford-bunny): their
/// alignment file, for tests on real laser scans.

#include <Eigen/Geometry>

#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::reconstruction::testing_support {

/// bun.conf: `bmesh FILE tx ty tz qx qy qz qw`; a scan point p maps into the
/// common frame as R(q)^T p + t (see the data README).
inline std::vector<std::pair<std::string, Eigen::Isometry3d>> readBunConf(const std::string& path) {
  std::vector<std::pair<std::string, Eigen::Isometry3d>> poses;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string tag, file;
    double tx, ty, tz, qx, qy, qz, qw;
    if (!(fields >> tag >> file >> tx >> ty >> tz >> qx >> qy >> qz >> qw) || tag != "bmesh") continue;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix().transpose();
    pose.translation() = Eigen::Vector3d(tx, ty, tz);
    poses.emplace_back(file, pose);
  }
  return poses;
}

}  // namespace icrkit::reconstruction::testing_support
