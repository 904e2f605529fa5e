#include <icrkit/reconstruction/registration/joint_refinement.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>

#include "cube_key.hpp"
#include "nearest_tracker.hpp"
#include "view_pairs.hpp"

#include <Eigen/Cholesky>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>

namespace icrkit::reconstruction {

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Centroids of the points (and their normals, made to agree in sign) per
// cube, in key order, thinned to at most `cap` by an even stride.
void reduceSources(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                   double voxel, std::size_t cap, std::vector<Eigen::Vector3d>& out_points,
                   std::vector<Eigen::Vector3d>& out_normals) {
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
    int count = 0;
  };
  std::map<std::int64_t, Cell> cells;
  for (std::size_t k = 0; k < points.size(); ++k) {
    Cell& c = cells[cubeKey(points[k], voxel)];
    c.sum += points[k];
    // Facing the sensor, so that the sum does not cancel.
    c.normal += normals[k].dot(points[k]) > 0 ? -normals[k] : normals[k];
    ++c.count;
  }
  std::vector<Eigen::Vector3d> p, n;
  for (const auto& [key, c] : cells) {
    if (!(c.normal.norm() > 0)) continue;
    p.push_back(c.sum / c.count);
    n.push_back(c.normal.normalized());
  }
  out_points.clear();
  out_normals.clear();
  const std::size_t keep = std::min(std::max<std::size_t>(cap, 1), p.size());
  const double stride = keep > 0 ? double(p.size()) / double(keep) : 1.0;
  for (std::size_t k = 0; k < keep; ++k) {
    const std::size_t at = static_cast<std::size_t>(double(k) * stride);
    out_points.push_back(p[at]);
    out_normals.push_back(n[at]);
  }
}

// One view's part of the normal equations: its sources against every other
// view's targets. Blocks indexed by view.
struct ViewEquations {
  std::map<std::pair<std::size_t, std::size_t>, Matrix6d> blocks;
  std::map<std::size_t, Vector6d> gradient;
  double weighted_sq = 0.0, weight = 0.0;
  std::size_t pairs = 0;
  std::vector<std::size_t> partners;  // views j with correspondences
};

using Tracker = NearestTracker<KdTree>;

Eigen::Isometry3d worldStep(const Vector6d& x, const Eigen::Vector3d& centre) {
  // x = [t; theta], a rotation about `centre` then a translation (world).
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  const double angle = x.tail<3>().norm();
  if (angle > 0) step.linear() = Eigen::AngleAxisd(angle, x.tail<3>() / angle).toRotationMatrix();
  step.translation() = centre - step.linear() * centre + x.head<3>();
  return step;
}

}  // namespace

JointRefinementResult refineJointly(const std::vector<std::vector<Eigen::Vector3d>>& points,
                                    const std::vector<std::vector<Eigen::Vector3d>>& normals,
                                    const std::vector<Eigen::Isometry3d>& poses,
                                    const JointRefinementParameters& params) {
  const std::size_t n = poses.size();
  if (points.size() != n || normals.size() != n)
    throw InputError("joint refinement", "", std::to_string(n) + " poses but " + std::to_string(points.size()) +
                                                 " point sets and " + std::to_string(normals.size()) + " normal sets");
  for (std::size_t i = 0; i < n; ++i)
    if (points[i].size() != normals[i].size())
      throw InputError("joint refinement", "view " + std::to_string(i),
                       std::to_string(points[i].size()) + " points but " + std::to_string(normals[i].size()) +
                           " normals");
  if (params.iterations < 0 || params.max_distances.empty() || !(params.kernel_width > 0) ||
      !(params.source_voxel_size > 0) || !(params.prior_sigma_translation > 0) || !(params.prior_sigma_rotation > 0))
    throw InputError("joint refinement", "", "iterations >= 0, pairing distances and positive kernel, cube edge and "
                                             "prior sigmas");
  for (double d : params.max_distances)
    if (!(d > 0)) throw InputError("joint refinement", "", "positive pairing distances");

  JointRefinementResult result;
  result.poses = poses;
  if (n < 2) return result;

  // Per view, in its sensor frame: the sources (every point, in cubes) and
  // the targets (the face-on points, in a search tree).
  const double min_cos = params.target_max_incidence >= M_PI / 2 ? -1.0 : std::cos(params.target_max_incidence);
  std::vector<std::vector<Eigen::Vector3d>> sources(n), source_normals(n);
  std::vector<std::vector<Eigen::Vector3d>> target_points(n), target_normals(n);
  std::vector<std::unique_ptr<KdTree>> trees(n);
  std::vector<char> usable(n, 0);  // not vector<bool>: the views are filled in parallel
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (points[i].size() < 3) return;
    reduceSources(points[i], normals[i], params.source_voxel_size, params.max_source_points, sources[i],
                  source_normals[i]);
    for (std::size_t k = 0; k < points[i].size(); ++k) {
      const double range = points[i][k].norm();
      if (range > 0 && std::abs(normals[i][k].dot(points[i][k])) >= min_cos * range) {
        target_points[i].push_back(points[i][k]);
        target_normals[i].push_back(normals[i][k].dot(points[i][k]) > 0 ? Eigen::Vector3d(-normals[i][k])
                                                                         : normals[i][k]);
      }
    }
    if (!target_points[i].empty()) trees[i] = std::make_unique<KdTree>(target_points[i]);
    usable[i] = !sources[i].empty();
  });

  // Rotations about the views' common centre keep the system well scaled.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::size_t counted = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (const Eigen::Vector3d& p : sources[i]) {
      centre += poses[i] * p;
      ++counted;
    }
  if (counted == 0) return result;
  centre /= double(counted);

  // Bounding spheres (sensor frame) to skip pairs that cannot overlap.
  std::vector<Eigen::Vector3d> sphere_centre(n, Eigen::Vector3d::Zero());
  std::vector<double> sphere_radius(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!usable[i]) continue;
    for (const Eigen::Vector3d& p : points[i]) sphere_centre[i] += p;
    sphere_centre[i] /= double(points[i].size());
    for (const Eigen::Vector3d& p : points[i])
      sphere_radius[i] = std::max(sphere_radius[i], (p - sphere_centre[i]).norm());
  }

  // Residuals in units of a depth camera's noise, so that the priors'
  // information is comparable.
  const double noise = 0.5 * params.kernel_width;
  const double residual_information = 1.0 / (noise * noise);
  Matrix6d prior = Matrix6d::Zero();
  prior.diagonal() << Eigen::Vector3d::Constant(1.0 / (params.prior_sigma_translation * params.prior_sigma_translation)),
      Eigen::Vector3d::Constant(1.0 / (params.prior_sigma_rotation * params.prior_sigma_rotation));
  std::vector<Vector6d> moved(n, Vector6d::Zero());  // accumulated step per view, for its prior

  // Per view, per partner view: its sources' searches of the partner's
  // targets (nearest_tracker.hpp), made when the pair first comes near.
  std::vector<std::vector<Tracker>> trackers(n, std::vector<Tracker>(n));
  const std::size_t stages = params.max_distances.size();
  for (int it = 0; it < params.iterations; ++it) {
    const std::size_t stage = std::min(
        stages - 1, static_cast<std::size_t>(it) * stages / static_cast<std::size_t>(std::max(1, params.iterations)));
    const double max_distance = params.max_distances[stage];
    const double width = std::min(params.kernel_width, max_distance);
    std::vector<ViewEquations> per_view(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      if (!usable[i]) return;
      ViewEquations& eq = per_view[i];
      const Eigen::Isometry3d& pi = result.poses[i];
      const Eigen::Vector3d world_sphere_i = pi * sphere_centre[i];
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i || !usable[j] || !trees[j]) continue;
        const Eigen::Isometry3d& pj = result.poses[j];
        if ((pj * sphere_centre[j] - world_sphere_i).norm() > sphere_radius[i] + sphere_radius[j] + max_distance)
          continue;
        const Eigen::Isometry3d j_from_i = pj.inverse() * pi;
        Matrix6d hii = Matrix6d::Zero(), hij = Matrix6d::Zero(), hjj = Matrix6d::Zero();
        Vector6d gi = Vector6d::Zero(), gj = Vector6d::Zero();
        double sq = 0.0, wsum = 0.0;
        std::size_t count = 0;
        Tracker& tracker = trackers[i][j];
        if (tracker.size() != sources[i].size()) tracker = Tracker(sources[i], Tracker::Parameters{});
        auto correspond = [&](std::size_t k, const Eigen::Vector3d& local, long t) {
          const std::size_t tk = static_cast<std::size_t>(t);
          // Both normals face their own sensors: the two sides of a thin
          // part disagree in sign and stay apart.
          const Eigen::Vector3d& nj = target_normals[j][tk];
          const Eigen::Vector3d ni = j_from_i.linear() * source_normals[i][k];
          if (nj.dot(ni) < params.min_normal_cosine) return;
          const Eigen::Vector3d n_world = pj.linear() * nj;
          const Eigen::Vector3d p_world = pj * local;
          const Eigen::Vector3d q_world = pj * target_points[j][tk];
          const double r = n_world.dot(p_world - q_world);
          const double u = r / width;
          const double w = residual_information / ((1.0 + u * u) * (1.0 + u * u));
          Vector6d ji, jj;
          ji.head<3>() = n_world;
          ji.tail<3>() = (p_world - centre).cross(n_world);
          jj.head<3>() = -n_world;
          jj.tail<3>() = -(q_world - centre).cross(n_world);
          hii.noalias() += w * ji * ji.transpose();
          hij.noalias() += w * ji * jj.transpose();
          hjj.noalias() += w * jj * jj.transpose();
          gi.noalias() += w * r * ji;
          gj.noalias() += w * r * jj;
          sq += w * r * r;
          wsum += w;
          ++count;
        };
        tracker.forEachNearest(sources[i], j_from_i, max_distance, target_points[j], *trees[j], correspond);
        if (count < params.min_pair_correspondences) continue;
        auto add = [&](std::size_t a, std::size_t b, const Matrix6d& m) {
          auto [at, fresh] = eq.blocks.try_emplace({a, b}, m);
          if (!fresh) at->second += m;
        };
        add(i, i, hii);
        add(i, j, hij);
        add(j, i, hij.transpose());
        add(j, j, hjj);
        auto addGradient = [&](std::size_t a, const Vector6d& g) {
          auto [at, fresh] = eq.gradient.try_emplace(a, g);
          if (!fresh) at->second += g;
        };
        addGradient(i, gi);
        addGradient(j, gj);
        eq.weighted_sq += sq;
        eq.weight += wsum;
        ++eq.pairs;
        eq.partners.push_back(j);
      }
    });

    // Summed in view order: the same bits for any thread count.
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(6 * n, 6 * n);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(6 * n);
    double sq = 0.0, wsum = 0.0;
    std::size_t pairs = 0;
    std::vector<std::pair<std::size_t, std::size_t>> linked;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j : per_view[i].partners) linked.emplace_back(i, j);
    result.linked_view_pairs = countUnorderedPairs(std::move(linked));
    for (const ViewEquations& eq : per_view) {
      for (const auto& [ab, m] : eq.blocks)
        h.block<6, 6>(6 * static_cast<Eigen::Index>(ab.first), 6 * static_cast<Eigen::Index>(ab.second)) += m;
      for (const auto& [a, v] : eq.gradient) g.segment<6>(6 * static_cast<Eigen::Index>(a)) += v;
      sq += eq.weighted_sq;
      wsum += eq.weight;
      pairs += eq.pairs;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Index at = 6 * static_cast<Eigen::Index>(i);
      h.block<6, 6>(at, at) += prior;
      g.segment<6>(at) += prior * moved[i];
    }
    result.pairs = pairs;
    result.rms_m = wsum > 0 ? std::sqrt(sq / wsum) : 0.0;
    result.iterations = it + 1;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(h);
    const Eigen::VectorXd step = -ldlt.solve(g);
    if (ldlt.info() != Eigen::Success || !step.allFinite()) break;
    double largest_t = 0.0, largest_r = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vector6d x = step.segment<6>(6 * static_cast<Eigen::Index>(i));
      result.poses[i] = worldStep(x, centre) * result.poses[i];
      moved[i] += x;
      largest_t = std::max(largest_t, x.head<3>().norm());
      largest_r = std::max(largest_r, x.tail<3>().norm());
    }
    if (stage == stages - 1 && largest_t < params.translation_epsilon && largest_r < params.rotation_epsilon) break;
  }
  return result;
}

}  // namespace icrkit::reconstruction
