#pragma once
// Private to libs/ndt: one row of a NeighbourGraph from a k-NN query, shared
// by the stand-alone graph and the smoothing pass's top-up of sparse windows.

#include <icrkit/core/kd_tree.hpp>
#include <icrkit/ndt/normal_orientation.hpp>

namespace icrkit::ndt {

// Row i: the graph.slots points of the tree nearest to points[i], itself
// left out (the tree's order of ties); unfilled slots keep their value.
inline void fillNearestNeighbourRow(const KdTree& tree, const std::vector<Eigen::Vector3d>& points, std::size_t i,
                                    NeighbourGraph& graph) {
  std::size_t slot = 0;
  for (const Neighbour& nb : tree.nearest(points[i], graph.slots + 1))
    if (nb.index != i && slot < graph.slots) graph.neighbours[i * graph.slots + slot++] = nb.index;
}

}  // namespace icrkit::ndt
