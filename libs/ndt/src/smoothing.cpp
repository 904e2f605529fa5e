#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/radius_cells.hpp>
#include <icrkit/ndt/fit_uncertainty.hpp>
#include <icrkit/ndt/normal_orientation.hpp>
#include <icrkit/ndt/smoothing.hpp>
#include <icrkit/ndt/symmetric_eigen3.hpp>

#include "nearest_neighbour_row.hpp"
#include "window_moments.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::ndt {

double flatness(const Eigen::Vector3d& eigenvalues, double floor) {
  const double l2 = eigenvalues(1);
  if (!(l2 > 0)) return 0.0;
  const double l3 = std::max(eigenvalues(2), floor * l2);
  return std::sqrt(l2 / l3);
}

namespace {

void validate(const PointCloud& cloud, const SmoothingParameters& params) {
  if (cloud.empty()) throw InputError("point cloud", "", "the cloud is empty; nothing to smooth");
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (!cloud.positions[i].allFinite())
      throw InputError("point cloud", "point " + std::to_string(i), "non-finite coordinate, expected finite x, y, z");
  params.validate();
}

// The input normals (unit, or zero for none) and the cosine a window's
// points must reach against the query point's; no normals: two-sided.
struct WindowSide {
  std::vector<Eigen::Vector3d> normals;
  double min_cosine = -1.0;

  bool keeps(std::size_t i, std::size_t j) const {
    const Eigen::Vector3d& a = normals[i];
    const Eigen::Vector3d& b = normals[j];
    return a.dot(b) >= min_cosine || a.squaredNorm() == 0.0 || b.squaredNorm() == 0.0;
  }
};

struct PassOutput {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;
  std::vector<int> cardinality;
  std::vector<double> flatness;
  std::vector<FitUncertainty> uncertainty;
  NeighbourGraph graph;  // the nearest points of each window, when asked for
};

// Writes the `slots` points of `window` nearest to input[i] (itself left
// out; ties in window order) into the graph's row i. A window with too few
// points (an isolated point, a sparse patch) is topped up by a k-NN query,
// so that the orientation graph still bridges gaps as a k-NN graph would.
void keepNearest(const std::vector<Eigen::Vector3d>& input, const KdTree& tree, std::size_t i,
                 const std::vector<std::size_t>& window, NeighbourGraph& graph) {
  constexpr std::size_t kMaxSlots = 32;
  const std::size_t slots = std::min(graph.slots, kMaxSlots);
  if (window.size() < slots + 1) {
    fillNearestNeighbourRow(tree, input, i, graph);
    return;
  }
  std::array<double, kMaxSlots> distance;
  std::array<std::size_t, kMaxSlots> index;
  std::size_t kept = 0;
  for (std::size_t j : window) {
    if (j == i) continue;
    const double d = (input[j] - input[i]).squaredNorm();
    if (kept == slots && !(d < distance[kept - 1])) continue;
    std::size_t at = kept < slots ? kept++ : kept - 1;
    while (at > 0 && d < distance[at - 1]) {
      distance[at] = distance[at - 1];
      index[at] = index[at - 1];
      --at;
    }
    distance[at] = d;
    index[at] = j;
  }
  for (std::size_t s = 0; s < kept; ++s) graph.neighbours[i * graph.slots + s] = index[s];
}

// One Jacobi pass: every window is taken from `input`.
PassOutput smoothingPass(const std::vector<Eigen::Vector3d>& input, double radius, double flatness_floor,
                         const WindowSide& side, std::size_t graph_slots, const ProgressCallback& progress,
                         const std::string& stage) {
  const std::size_t n = input.size();
  // Only the orientation graph's top-up of sparse windows asks for k nearest.
  std::optional<KdTree> tree;
  if (graph_slots > 0) tree.emplace(input);
  PassOutput out;
  out.positions.resize(n);
  out.normals.assign(n, Eigen::Vector3d::Zero());
  out.cardinality.resize(n);
  out.flatness.assign(n, 0.0);
  out.uncertainty.assign(n, FitUncertainty{M_PI / 2, radius});
  out.graph.slots = graph_slots;
  out.graph.neighbours.assign(n * graph_slots, n);
  std::atomic<std::size_t> done{0};
  const RadiusCells cells(input, radius);
  const double radius_sq = radius * radius;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cellCount(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
    // One set of buffers per task, reused for every cube and point.
    CandidatePositions near;
    std::vector<std::uint32_t> slots;
    std::vector<std::size_t> window;
    std::size_t points = 0;
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      near.gather(input, cells, c);
      for (const std::uint32_t* it = cells.cellBegin(c); it != cells.cellEnd(c); ++it, ++points) {
        const std::size_t i = *it;
        const Eigen::Vector3d& p = input[i];
        // Mean and covariance about the query point (shifted data keeps the
        // sums small and exact-ish), over the candidates within the radius
        // on the query's side, in the cubes' order: fixed for a given cloud,
        // so the sums have the same bits on every run and thread count.
        const std::size_t within = near.within(p, radius_sq, slots);
        WindowMoments m;
        window.clear();
        for (std::size_t s = 0; s < within; ++s) {
          const std::size_t j = near.index[slots[s]];
          if (!side.normals.empty() && !side.keeps(i, j)) continue;
          m.add(near.offset(slots[s], p));
          if (graph_slots > 0) window.push_back(j);
        }
        const std::size_t count = m.count;
        out.cardinality[i] = static_cast<int>(count);
        if (graph_slots > 0) keepNearest(input, *tree, i, window, out.graph);
        if (count < 3) {
          out.positions[i] = p;
          continue;
        }
        const double inv = 1.0 / static_cast<double>(count);
        const Eigen::Vector3d mean_offset = m.sum * inv;
        const Eigen::Matrix3d covariance = m.outer() * inv - mean_offset * mean_offset.transpose();
        const SymmetricEigen3 eigen = eigenSymmetric3(covariance);
        const Eigen::Vector3d v3 = eigen.vectors.col(2);
        out.positions[i] = p + v3 * mean_offset.dot(v3);  // eq. (1): mu - p = mean_offset
        out.normals[i] = v3;
        out.flatness[i] = flatness(eigen.values, flatness_floor);
        out.uncertainty[i] =
            planeFitUncertainty(eigen.values, eigen.vectors, count, -mean_offset, radius, FittedPoint::Projected);
      }
    }
    if (progress) progress(stage, done.fetch_add(points) + points, n);
  });
  return out;
}

}  // namespace

void SmoothingParameters::validate() const {
  if (!radius.valid())
    throw InputError("SmoothingParameters::radius", "",
                     "the window radius must be positive, got " + formatLength(radius));
  if (passes < 1)
    throw InputError("SmoothingParameters::passes", "", "at least one pass, got " + std::to_string(passes));
  if (!(max_normal_angle > 0))
    throw InputError("SmoothingParameters::max_normal_angle", "",
                     "expected an angle > 0 radians, got " + std::to_string(max_normal_angle));
  if (!(std::isfinite(flatness_floor) && flatness_floor > 0 && flatness_floor <= 1))
    throw InputError("SmoothingParameters::flatness_floor", "", "expected a fraction in (0, 1]");
  preselection.validate();
}

SmoothingReport smoothPointCloud(PointCloud& cloud, const SmoothingParameters& params,
                                 const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  validate(cloud, params);
  SmoothingReport summary;
  const std::size_t n = cloud.size();
  summary.points = n;
  summary.passes = params.passes;
  // The spacing costs a k-NN query per point; only a relative radius needs it.
  if (params.radius.relative) summary.median_spacing_m = nearestNeighbourSpacing(cloud.positions).median;
  summary.radius_m = params.radius.metresFor(summary.median_spacing_m);
  if (!(summary.radius_m > 0))
    throw InputError("SmoothingParameters::radius", "",
                     "the median point spacing is 0 (duplicated points); give the radius in metres");

  const std::vector<Eigen::Vector3d> original = cloud.positions;
  std::vector<int> cardinality;
  std::vector<double> flat;
  std::vector<FitUncertainty> uncertainty;
  std::vector<Eigen::Vector3d> normals;
  // Without a viewpoint, normals are oriented over a neighbour graph; the
  // last pass's windows hold each point's nearest neighbours already, so the
  // graph costs no second k-d tree and no k-NN queries.
  if (!params.viewpoints.empty() && params.viewpoints.size() != n)
    throw InputError("SmoothingParameters::viewpoints", "",
                     "expected one viewpoint per point (" + std::to_string(n) + "), got " +
                         std::to_string(params.viewpoints.size()));
  const bool own_sensors = !params.viewpoint && !params.viewpoints.empty();
  const std::size_t graph_slots = params.viewpoint || own_sensors ? 0 : NormalOrientationParameters{}.neighbours;
  NeighbourGraph graph;
  // The sides come from the input normals in every pass: later passes'
  // v3 estimates are made from one-sided windows already.
  WindowSide side;
  if (params.max_normal_angle < M_PI && cloud.hasNormals()) {
    side.min_cosine = std::cos(params.max_normal_angle);
    side.normals.reserve(n);
    for (const Eigen::Vector3d& normal : cloud.normals)
      side.normals.push_back(normal.squaredNorm() > 0 ? Eigen::Vector3d(normal.normalized()) : Eigen::Vector3d::Zero());
  }
  for (int pass = 0; pass < params.passes; ++pass) {
    const bool last = pass + 1 == params.passes;
    PassOutput out = smoothingPass(cloud.positions, summary.radius_m, params.flatness_floor, side, last ? graph_slots : 0,
                                   progress,
                                   "smoothing pass " + std::to_string(pass + 1) + "/" + std::to_string(params.passes));
    if (pass == 0) {
      cardinality = std::move(out.cardinality);
      flat = std::move(out.flatness);
      uncertainty = std::move(out.uncertainty);
    }
    cloud.positions = std::move(out.positions);
    normals = std::move(out.normals);
    if (last) graph = std::move(out.graph);
  }
  // A window of fewer than 3 points has no plane: such a point keeps the
  // normal it came with (a fused cloud's, say) rather than none at all.
  if (cloud.hasNormals())
    for (std::size_t i = 0; i < n; ++i)
      if (normals[i].squaredNorm() == 0.0) normals[i] = cloud.normals[i];
  cloud.normals = std::move(normals);
  if (params.viewpoint) {
    orientNormals(cloud, params.viewpoint);
  } else if (own_sensors) {
    for (std::size_t i = 0; i < n; ++i)
      if (cloud.normals[i].dot(params.viewpoints[i] - cloud.positions[i]) < 0) cloud.normals[i] = -cloud.normals[i];
  } else {
    orientNormalsOverGraph(cloud, graph);
  }

  // Serial sums in index order: the same bits whatever the thread count.
  double displacement_sum = 0;
  std::vector<double> displacement(n);
  for (std::size_t i = 0; i < n; ++i) {
    displacement[i] = (cloud.positions[i] - original[i]).norm();
    displacement_sum += displacement[i];
    summary.max_displacement_m = std::max(summary.max_displacement_m, displacement[i]);
    if (cardinality[i] < 3) ++summary.small_windows;
  }
  summary.mean_displacement_m = displacement_sum / static_cast<double>(n);

  auto& card_attr = cloud.attributes.add("cardinality", ScalarType::Int32, n);
  auto& flat_attr = cloud.attributes.add("flatness", ScalarType::Float32, n);
  auto& disp_attr = cloud.attributes.add("displacement", ScalarType::Float32, n);
  auto& normal_sigma = cloud.attributes.add(kNormalSigmaAttribute, ScalarType::Float32, n);
  auto& position_sigma = cloud.attributes.add(kPositionSigmaAttribute, ScalarType::Float32, n);
  for (std::size_t i = 0; i < n; ++i) {
    card_attr.values[i] = cardinality[i];
    // As the file will hold it, so that a preselection re-run from the file
    // (icrkit evaluate --preselection) decides exactly as this one.
    flat_attr.values[i] = representAs(ScalarType::Float32, flat[i]);
    disp_attr.values[i] = displacement[i];
    normal_sigma.values[i] = representAs(ScalarType::Float32, uncertainty[i].normal_sigma);
    position_sigma.values[i] = representAs(ScalarType::Float32, uncertainty[i].position_sigma);
  }
  Preselection chosen = preselect(card_attr.values, flat_attr.values, params.preselection);
  summary.preselection = chosen.summary;
  if (params.preselection.rule == PreselectionRule::None)
    cloud.attributes.remove("excluded");  // an input's old flags would no longer describe it
  else
    cloud.attributes.add("excluded", ScalarType::UInt8,
                         std::vector<double>(chosen.excluded.begin(), chosen.excluded.end()));
  summary.time_ms = millisecondsSince(start);
  return summary;
}

}  // namespace icrkit::ndt
