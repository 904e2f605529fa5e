/// \file
/// OctoMap used directly (not through MRPT's COctoMap, which passes its
/// `pruning` flag on as OctoMap's lazy_eval and so leaves inner nodes stale).

#include <icrkit/reconstruction/fusion/octree_fusion.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>

#include "key_bitmap.hpp"

#include <octomap/OcTree.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

namespace icrkit::reconstruction {

namespace {

// What one scan does to the octree: the voxels its rays cross and those
// its points end in.
struct TracedScan {
  KeyBitmap free_keys, hit_keys;
};

}  // namespace

struct OctreeFusion::Impl {
  explicit Impl(const OctreeFusionParameters& p) : params(p), tree(p.resolution) {}

  OctreeFusionParameters params;
  octomap::OcTree tree;
  bool finished = false;
  // Set when an insertion failed part-way (out of memory): the tree may then
  // hold some of its scans, so later calls refuse.
  std::string broken;
  void refuseIfBroken(const char* call) const {
    if (!broken.empty()) throw std::logic_error(std::string("OctreeFusion::") + call + " after a failed insert: " + broken);
  }
  // Runs an insertion; a failure marks the fusion broken.
  template <class Insert>
  void guarded(Insert insert) {
    try {
      insert();
    } catch (const std::exception& e) {
      broken = e.what();
      throw;
    }
  }
  double time_ms = 0.0;
  OctreeFusionReport report;
  // The candidates seen so far, in insertion order: the fused model.
  std::vector<Eigen::Vector3d> points;
  std::vector<std::int32_t> views;
  std::vector<std::uint32_t> pixels;
  std::vector<std::uint32_t> origins;  // index into `viewpoints`, one per scan
  std::vector<Eigen::Vector3d> viewpoints;

  // The octree update and the bookkeeping of one traced scan, in order.
  void apply(const RangeScan& scan, const std::vector<std::uint8_t>& candidate, const TracedScan& traced);
};

namespace {

octomap::point3d toOcto(const Eigen::Vector3d& v) {
  return octomap::point3d(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}

// Clips the segment o..end to `box` (slab method); false when it misses.
bool clipToBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& o, const Eigen::Vector3d& end, double& t0,
               double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  const Eigen::Vector3d d = end - o;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12) {
      if (o[a] < box.min()[a] || o[a] > box.max()[a]) return false;
      continue;
    }
    double ta = (box.min()[a] - o[a]) / d[a], tb = (box.max()[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

OctreeFusion::OctreeFusion(const OctreeFusionParameters& params) {
  if (!(params.resolution > 0) || !std::isfinite(params.resolution))
    throw InputError("resolution", "", "must be a positive number of metres");
  for (double p : {params.prob_hit, params.prob_miss, params.occupancy_threshold, params.clamping_min,
                   params.clamping_max})
    if (!(p > 0 && p < 1)) throw InputError("octree probabilities", "", "must lie in (0, 1)");
  impl_ = std::make_unique<Impl>(params);
  octomap::OcTree& tree = impl_->tree;
  tree.setProbHit(params.prob_hit);
  tree.setProbMiss(params.prob_miss);
  tree.setClampingThresMin(params.clamping_min);
  tree.setClampingThresMax(params.clamping_max);
  tree.setOccupancyThres(params.occupancy_threshold);
}

OctreeFusion::~OctreeFusion() = default;

namespace {

void checkCandidates(const RangeScan& scan, const std::vector<std::uint8_t>& candidate) {
  if (!candidate.empty() && candidate.size() != scan.points.size())
    throw InputError("scan " + std::to_string(scan.index), "",
                     "candidate mask has " + std::to_string(candidate.size()) + " flags for " +
                         std::to_string(scan.points.size()) + " points");
}

// The costly part of an insertion. It reads only the tree's resolution
// (computeRayKeys and coordToKeyChecked are const and never look at the
// nodes), so scans can be traced in parallel.
TracedScan traceScan(const octomap::OcTree& tree, const OctreeFusionParameters& params, const RangeScan& scan) {
  const bool bounded = !params.bounds.isEmpty();
  const Eigen::Vector3d o = scan.sensor_pose.translation();
  const double max_range = params.max_range.value_or(scan.max_range);
  // The update is OctoMap's insertPointCloud (one update per voxel and
  // scan, a voxel both hit and crossed counts as hit), with the rays clipped
  // to `bounds` here: OctoMap's own BBX limit walks each ray back from its
  // end point and stops at the box, so a ray ending outside the box (on the
  // table, the background) would carve nothing inside it, and those are
  // exactly the rays that see through the space around the object.
  TracedScan traced;
  // Keys inside the box (and a margin for rounding at its faces) in
  // bitmaps of at most 16 MB; the others, and all of them without a box,
  // in hash sets.
  octomap::OcTreeKey min_key, max_key;
  if (bounded && tree.coordToKeyChecked(toOcto(params.bounds.min()), min_key) &&
      tree.coordToKeyChecked(toOcto(params.bounds.max()), max_key)) {
    std::size_t bits = 1;
    for (int a = 0; a < 3; ++a) {
      min_key[a] = static_cast<octomap::key_type>(std::max(0, int(min_key[a]) - 2));
      max_key[a] = static_cast<octomap::key_type>(std::min(65535, int(max_key[a]) + 2));
      bits *= static_cast<std::size_t>(max_key[a] - min_key[a] + 1);
    }
    if (bits <= (std::size_t{1} << 27)) {
      traced.free_keys = KeyBitmap(min_key, max_key);
      traced.hit_keys = KeyBitmap(min_key, max_key);
    }
  }
  octomap::KeyRay ray;
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
    if (hit && tree.coordToKeyChecked(toOcto(end), key)) traced.hit_keys.insert(key);
    double t0 = 0.0, t1 = 1.0;
    if (bounded && !clipToBox(params.bounds, o, end, t0, t1)) continue;
    if (tree.computeRayKeys(toOcto(o + t0 * (end - o)), toOcto(o + t1 * (end - o)), ray))
      for (const octomap::OcTreeKey& key : ray) traced.free_keys.insert(key);
  }
  return traced;
}

}  // namespace

void OctreeFusion::Impl::apply(const RangeScan& scan, const std::vector<std::uint8_t>& candidate,
                               const TracedScan& traced) {
  const bool bounded = !params.bounds.isEmpty();
  const Eigen::Vector3d o = scan.sensor_pose.translation();
  const double max_range = params.max_range.value_or(scan.max_range);
  // Inner nodes are brought up to date once at the end (OctoMap's
  // documented use of lazy evaluation); leaves are exact after every scan.
  // Each voxel is updated once per scan, so the order of the voxels does
  // not matter: the leaves end the same in any.
  traced.free_keys.forEach([&](const octomap::OcTreeKey& key) {
    if (!traced.hit_keys.contains(key)) tree.updateNode(key, false, true);
  });
  traced.hit_keys.forEach([&](const octomap::OcTreeKey& key) { tree.updateNode(key, true, true); });

  const std::uint32_t origin = static_cast<std::uint32_t>(viewpoints.size());
  viewpoints.push_back(o);
  std::size_t candidates = 0;
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    if (!candidate.empty() && !candidate[k]) continue;
    ++candidates;
    const Eigen::Vector3d& p = scan.points[k];
    if ((bounded && !params.bounds.contains(p)) || (max_range > 0 && (p - o).norm() > max_range)) {
      ++report.dropped_outside;
      continue;
    }
    points.push_back(p);
    views.push_back(static_cast<std::int32_t>(scan.index));
    pixels.push_back(k < scan.pixels.size() ? scan.pixels[k] : 0u);
    origins.push_back(origin);
  }
  report.points_in += candidates;
  ++report.scans;
}

void OctreeFusion::insert(const RangeScan& scan, const std::vector<std::uint8_t>& candidate) {
  if (impl_->finished) throw std::logic_error("OctreeFusion::insert after finish()");
  checkCandidates(scan, candidate);
  impl_->refuseIfBroken("insert");
  const auto start = std::chrono::steady_clock::now();
  impl_->guarded([&] { impl_->apply(scan, candidate, traceScan(impl_->tree, impl_->params, scan)); });
  impl_->time_ms += millisecondsSince(start);
}

void OctreeFusion::insert(const std::vector<RangeScan>& scans, const std::vector<std::vector<std::uint8_t>>& candidates) {
  if (impl_->finished) throw std::logic_error("OctreeFusion::insert after finish()");
  if (!candidates.empty() && candidates.size() != scans.size())
    throw InputError("scans", "",
                     std::to_string(candidates.size()) + " candidate masks for " + std::to_string(scans.size()) +
                         " scans");
  static const std::vector<std::uint8_t> kEveryPoint;
  auto maskOf = [&](std::size_t i) -> const std::vector<std::uint8_t>& {
    return candidates.empty() ? kEveryPoint : candidates[i];
  };
  for (std::size_t i = 0; i < scans.size(); ++i) checkCandidates(scans[i], maskOf(i));
  impl_->refuseIfBroken("insert");
  const auto start = std::chrono::steady_clock::now();
  // Traced in parallel, applied in scan order as each is ready: a scan is
  // applied while the next ones are traced. The tree is the same as
  // applying them one by one.
  using Traced = std::pair<std::size_t, std::shared_ptr<TracedScan>>;
  std::size_t next = 0;
  auto emit = [&](tbb::flow_control& control) -> std::size_t {
    if (next == scans.size()) control.stop();
    return next++;
  };
  auto trace = [&](std::size_t i) {
    return Traced(i, std::make_shared<TracedScan>(traceScan(impl_->tree, impl_->params, scans[i])));
  };
  auto apply = [&](const Traced& traced) { impl_->apply(scans[traced.first], maskOf(traced.first), *traced.second); };
  impl_->guarded([&] {
    tbb::parallel_pipeline(2 * static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency())),
                           tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order, emit) &
                               tbb::make_filter<std::size_t, Traced>(tbb::filter_mode::parallel, trace) &
                               tbb::make_filter<Traced, void>(tbb::filter_mode::serial_in_order, apply));
  });
  impl_->time_ms += millisecondsSince(start);
}

OctreeFusionResult OctreeFusion::finish() {
  if (impl_->finished) throw std::logic_error("OctreeFusion::finish called twice");
  impl_->refuseIfBroken("finish");
  const auto start = std::chrono::steady_clock::now();
  Impl& s = *impl_;
  s.finished = true;
  octomap::OcTree& tree = s.tree;
  tree.updateInnerOccupancy();

  OctreeFusionResult result;
  OctreeFusionReport& report = result.report;
  report = s.report;
  report.kept_per_scan.assign(s.viewpoints.size(), 0);
  PointCloud& out = result.points;
  std::vector<double> view, pixel, vx, vy, vz;
  // Each candidate's cell, looked up in parallel (the tree is only read
  // now), then kept or counted in order.
  enum : std::uint8_t { kKept, kOutside, kFree };
  std::vector<std::uint8_t> fate(s.points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.points.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        const Eigen::Vector3d& p = s.points[k];
                        const octomap::OcTreeNode* node = tree.search(
                            static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
                        fate[k] = node == nullptr ? kOutside : tree.isNodeOccupied(node) ? kKept : kFree;
                      }
                    });
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    const Eigen::Vector3d& p = s.points[k];
    if (fate[k] == kOutside) {
      ++report.dropped_outside;
      continue;
    }
    if (fate[k] == kFree) {
      ++report.dropped_free;
      continue;
    }
    const Eigen::Vector3d& o = s.viewpoints[s.origins[k]];
    out.positions.push_back(p);
    view.push_back(static_cast<double>(s.views[k]));
    pixel.push_back(static_cast<double>(s.pixels[k]));
    vx.push_back(o.x());
    vy.push_back(o.y());
    vz.push_back(o.z());
    ++report.kept_per_scan[s.origins[k]];
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
  // Release the model and the octree now rather than with the object.
  s.points = {};
  s.views = {};
  s.pixels = {};
  s.origins = {};
  s.tree.clear();
  report.time_ms = s.time_ms + millisecondsSince(start);
  return result;
}

OctreeFusionResult fuseScans(const std::vector<RangeScan>& scans, const OctreeFusionParameters& params) {
  OctreeFusion fusion(params);
  for (const RangeScan& scan : scans) fusion.insert(scan);
  return fusion.finish();
}

std::vector<Eigen::Vector3d> fusionViewpoints(const PointCloud& cloud) {
  const AttributeSet& a = cloud.attributes;
  if (!a.has("viewpoint_x") || !a.has("viewpoint_y") || !a.has("viewpoint_z")) return {};
  const auto& vx = a.get("viewpoint_x").values;
  const auto& vy = a.get("viewpoint_y").values;
  const auto& vz = a.get("viewpoint_z").values;
  std::vector<Eigen::Vector3d> viewpoints;
  viewpoints.reserve(cloud.positions.size());
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) viewpoints.emplace_back(vx[i], vy[i], vz[i]);
  return viewpoints;
}

}  // namespace icrkit::reconstruction
