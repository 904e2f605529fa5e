/// \file
/// OctoMap used directly (not through MRPT's COctoMap, which passes its
/// `pruning` flag on as OctoMap's lazy_eval and so leaves inner nodes stale).

#include <icrkit/reconstruction/octree_fusion.hpp>

#include <icrkit/core/error.hpp>

#include <octomap/OcTree.h>

#include <chrono>
#include <algorithm>
#include <cmath>

namespace icrkit::reconstruction {

OctreeFusionResult fuseScans(const std::vector<RangeScan>& scans, const OctreeFusionParameters& params) {
  const auto start = std::chrono::steady_clock::now();
  if (!(params.resolution > 0) || !std::isfinite(params.resolution))
    throw InputError("resolution", "", "must be a positive number of metres");
  for (double p : {params.prob_hit, params.prob_miss, params.occupancy_threshold, params.clamping_min,
                   params.clamping_max})
    if (!(p > 0 && p < 1)) throw InputError("octree probabilities", "", "must lie in (0, 1)");

  octomap::OcTree tree(params.resolution);
  tree.setProbHit(params.prob_hit);
  tree.setProbMiss(params.prob_miss);
  tree.setClampingThresMin(params.clamping_min);
  tree.setClampingThresMax(params.clamping_max);
  tree.setOccupancyThres(params.occupancy_threshold);
  const bool bounded = !params.bounds.isEmpty();
  auto toOcto = [](const Eigen::Vector3d& v) {
    return octomap::point3d(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
  };

  OctreeFusionResult result;
  OctreeFusionReport& report = result.report;
  report.scans = scans.size();
  // The update is OctoMap's insertPointCloud (one update per voxel and
  // scan, a voxel both hit and crossed counts as hit), with the rays clipped
  // to `bounds` here: OctoMap's own BBX limit walks each ray back from its
  // end point and stops at the box, so a ray ending outside the box (on the
  // table, the background) would carve nothing inside it, and those are
  // exactly the rays that see through the space around the object.
  octomap::KeyRay ray;
  for (const RangeScan& scan : scans) {
    const Eigen::Vector3d o = scan.sensor_pose.translation();
    const double max_range = params.max_range > 0 ? params.max_range : scan.max_range;
    octomap::KeySet free_keys, hit_keys;
    for (const Eigen::Vector3d& p : scan.points) {
      Eigen::Vector3d end = p;
      bool hit = true;
      const double length = (p - o).norm();
      if (max_range > 0 && length > max_range) {
        end = o + (p - o) * (max_range / length);
        hit = false;
      }
      if (bounded && !params.bounds.contains(end)) hit = false;
      octomap::OcTreeKey key;
      if (hit && tree.coordToKeyChecked(toOcto(end), key)) hit_keys.insert(key);
      // Clip the segment o..end to the box (slab method).
      double t0 = 0.0, t1 = 1.0;
      if (bounded) {
        const Eigen::Vector3d d = end - o;
        bool inside = true;
        for (int a = 0; a < 3 && inside; ++a) {
          if (std::abs(d[a]) < 1e-12) {
            inside = o[a] >= params.bounds.min()[a] && o[a] <= params.bounds.max()[a];
            continue;
          }
          double ta = (params.bounds.min()[a] - o[a]) / d[a], tb = (params.bounds.max()[a] - o[a]) / d[a];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          inside = t0 <= t1;
        }
        if (!inside) continue;
      }
      if (tree.computeRayKeys(toOcto(o + t0 * (end - o)), toOcto(o + t1 * (end - o)), ray))
        free_keys.insert(ray.begin(), ray.end());
    }
    // Inner nodes are brought up to date once at the end (OctoMap's
    // documented use of lazy evaluation); leaves are exact after every scan.
    for (const octomap::OcTreeKey& key : free_keys)
      if (hit_keys.find(key) == hit_keys.end()) tree.updateNode(key, false, true);
    for (const octomap::OcTreeKey& key : hit_keys) tree.updateNode(key, true, true);
    report.points_in += scan.points.size();
  }
  tree.updateInnerOccupancy();

  PointCloud& out = result.points;
  std::vector<double> view, pixel, vx, vy, vz;
  report.kept_per_scan.assign(scans.size(), 0);
  for (std::size_t s = 0; s < scans.size(); ++s) {
    const RangeScan& scan = scans[s];
    const Eigen::Vector3d o = scan.sensor_pose.translation();
    const double max_range = params.max_range > 0 ? params.max_range : scan.max_range;
    for (std::size_t k = 0; k < scan.points.size(); ++k) {
      const Eigen::Vector3d& p = scan.points[k];
      if ((bounded && !params.bounds.contains(p)) || (max_range > 0 && (p - o).norm() > max_range)) {
        ++report.dropped_outside;
        continue;
      }
      const octomap::OcTreeNode* node =
          tree.search(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
      if (node == nullptr) {
        ++report.dropped_outside;
        continue;
      }
      if (!tree.isNodeOccupied(node)) {
        ++report.dropped_free;
        continue;
      }
      out.positions.push_back(p);
      view.push_back(static_cast<double>(scan.index));
      pixel.push_back(k < scan.pixels.size() ? static_cast<double>(scan.pixels[k]) : 0.0);
      vx.push_back(o.x());
      vy.push_back(o.y());
      vz.push_back(o.z());
      ++report.kept_per_scan[s];
    }
  }
  report.kept = out.positions.size();
  out.attributes.add("view", ScalarType::Int32, std::move(view));
  out.attributes.add("pixel", ScalarType::UInt32, std::move(pixel));
  out.attributes.add("viewpoint_x", ScalarType::Float64, std::move(vx));
  out.attributes.add("viewpoint_y", ScalarType::Float64, std::move(vy));
  out.attributes.add("viewpoint_z", ScalarType::Float64, std::move(vz));

  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    ++report.leaves;
    report.occupied_leaves += tree.isNodeOccupied(*it);
  }
  report.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace icrkit::reconstruction
