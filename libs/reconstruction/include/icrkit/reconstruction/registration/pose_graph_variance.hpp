#pragma once
/// \file
/// Variance component estimation for a solved pose graph (Foerstner 1979;
/// Koch, "Parameter Estimation and Hypothesis Testing in Linear Models",
/// ch. 3.6): how precise each group of edges (pair registrations, the
/// robot's reported poses, its odometry) really was on this data, relative
/// to the information it was given.
///
/// For a group g the estimate is sigma_g^2 = sum_e e^T W_e e / sum_e r_e,
/// with W_e the edge's information times its final robust weight and r_e
/// its redundancy: 6 - tr(W_e J_e N^-1 J_e^T), N the normal matrix of the
/// free nodes at the solution. The redundancy is what the residual-only
/// estimate (median chi-square against 6 degrees of freedom) leaves out:
/// a group that makes most of the solution it is measured against has
/// small residuals because it is fitted, not because it is precise, and
/// the redundancy gives such a group correspondingly few degrees of
/// freedom. Scaling each group's information by 1 / sigma_g^2 and solving
/// again, until every sigma_g^2 is near 1, weighs the groups as the data
/// says.
///
/// N is inverted densely: graphs of up to `max_free_nodes` free nodes
/// (the scans of one object: tens to a few hundred).

#include <icrkit/reconstruction/registration/pose_graph.hpp>

#include <cstddef>
#include <optional>
#include <vector>

namespace icrkit::reconstruction {

struct VarianceComponent {
  double variance_factor = 1.0;  ///< sigma_g^2: > 1 less precise than stated
  double redundancy = 0.0;       ///< sum of the group's r_e (degrees of freedom)
  std::size_t edges = 0;
};

/// `group[e]` is edge e's group in [0, groups) or -1 (not estimated, but
/// part of the solution). Nothing when the graph has more than
/// `max_free_nodes` free nodes or N is singular. A group with (almost) no
/// redundancy keeps factor 1.
std::optional<std::vector<VarianceComponent>> estimateVarianceComponents(const PoseGraph& graph,
                                                                          const PoseGraphResult& solved,
                                                                          const std::vector<int>& group, int groups,
                                                                          std::size_t max_free_nodes = 300);

}  // namespace icrkit::reconstruction
