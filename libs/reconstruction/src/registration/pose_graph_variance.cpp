#include <icrkit/reconstruction/registration/pose_graph_variance.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <limits>

namespace icrkit::reconstruction {

std::optional<std::vector<VarianceComponent>> estimateVarianceComponents(const PoseGraph& graph,
                                                                          const PoseGraphResult& solved,
                                                                          const std::vector<int>& group, int groups,
                                                                          std::size_t max_free_nodes) {
  const std::size_t n = graph.poses.size();
  if (group.size() != graph.edges.size() || solved.poses.size() != n || groups <= 0) return std::nullopt;
  constexpr std::size_t kFixed = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> slot(n, 0);
  for (std::size_t f : graph.fixed)
    if (f < n) slot[f] = kFixed;
  std::size_t free_nodes = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (slot[i] != kFixed) slot[i] = free_nodes++;
  if (free_nodes == 0 || free_nodes > max_free_nodes) return std::nullopt;

  const auto& weights = solved.report.edge_weights;
  auto weighted = [&](std::size_t e) {
    const double w = e < weights.size() ? weights[e] : 1.0;
    return Matrix6d(w * 0.5 * (graph.edges[e].information + graph.edges[e].information.transpose()));
  };
  const Eigen::Index dim = static_cast<Eigen::Index>(6 * free_nodes);
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(dim, dim);
  std::vector<Matrix6d> ja(graph.edges.size()), jb(graph.edges.size());
  std::vector<Vector6d> error(graph.edges.size());
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    const PoseGraphEdge& edge = graph.edges[e];
    error[e] = poseGraphEdgeError(solved.poses[edge.from], solved.poses[edge.to], edge.measurement, &ja[e], &jb[e]);
    const Matrix6d w = weighted(e);
    const std::size_t a = slot[edge.from], b = slot[edge.to];
    const Eigen::Index ia = static_cast<Eigen::Index>(6 * a), ib = static_cast<Eigen::Index>(6 * b);
    if (a != kFixed) normal.block<6, 6>(ia, ia) += ja[e].transpose() * w * ja[e];
    if (b != kFixed) normal.block<6, 6>(ib, ib) += jb[e].transpose() * w * jb[e];
    if (a != kFixed && b != kFixed) {
      const Matrix6d cross = ja[e].transpose() * w * jb[e];
      normal.block<6, 6>(ia, ib) += cross;
      normal.block<6, 6>(ib, ia) += cross.transpose();
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(normal);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return std::nullopt;
  const Eigen::MatrixXd covariance = ldlt.solve(Eigen::MatrixXd::Identity(dim, dim));

  std::vector<double> sum_sq(static_cast<std::size_t>(groups), 0.0), sum_r(static_cast<std::size_t>(groups), 0.0);
  std::vector<VarianceComponent> result(static_cast<std::size_t>(groups));
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    if (group[e] < 0 || group[e] >= groups) continue;
    const PoseGraphEdge& edge = graph.edges[e];
    const Matrix6d w = weighted(e);
    const std::size_t a = slot[edge.from], b = slot[edge.to];
    // J_e N^-1 J_e^T from the blocks of the two nodes the edge touches.
    Matrix6d projected = Matrix6d::Zero();
    const Eigen::Index ia = static_cast<Eigen::Index>(6 * a), ib = static_cast<Eigen::Index>(6 * b);
    if (a != kFixed) projected += ja[e] * covariance.block<6, 6>(ia, ia) * ja[e].transpose();
    if (b != kFixed) projected += jb[e] * covariance.block<6, 6>(ib, ib) * jb[e].transpose();
    if (a != kFixed && b != kFixed) {
      const Matrix6d cross = ja[e] * covariance.block<6, 6>(ia, ib) * jb[e].transpose();
      projected += cross + cross.transpose();
    }
    const double redundancy = std::clamp(6.0 - (w * projected).trace(), 0.0, 6.0);
    const std::size_t g = static_cast<std::size_t>(group[e]);
    sum_sq[g] += error[e].dot(w * error[e]);
    sum_r[g] += redundancy;
    ++result[g].edges;
  }
  for (std::size_t g = 0; g < result.size(); ++g) {
    result[g].redundancy = sum_r[g];
    if (sum_r[g] > 0.5) result[g].variance_factor = sum_sq[g] / sum_r[g];
  }
  return result;
}

}  // namespace icrkit::reconstruction
