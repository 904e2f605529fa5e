#include "hole_triangulation.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstddef>
#include <limits>

namespace icrkit::reconstruction {

PolygonTriangulation triangulatePolygon(const std::vector<Eigen::Vector3d>& positions,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        const std::function<bool(int, int)>& chord_allowed,
                                        FillFacing facing) {
  PolygonTriangulation result;
  const int n = static_cast<int>(positions.size());
  if (n < 3 || normals.size() != positions.size()) return result;
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const auto at = [n](int i, int j) { return static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + j; };
  // cost[i, j]: best triangulation of the sub-polygon w_i ... w_j closed by
  // the chord (i, j); split[i, j]: its apex k.
  std::vector<double> cost(static_cast<std::size_t>(n) * n, kNone);
  std::vector<int> split(static_cast<std::size_t>(n) * n, -1);
  std::vector<std::uint8_t> allowed(static_cast<std::size_t>(n) * n, 0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      allowed[at(i, j)] = (j == i + 1 || (i == 0 && j == n - 1)) ? 1 : chord_allowed(i, j) ? 1 : 0;
  for (int i = 0; i + 1 < n; ++i) cost[at(i, i + 1)] = 0.0;
  const auto weight = [&](int i, int k, int j) {
    const Eigen::Vector3d normal = (positions[k] - positions[i]).cross(positions[j] - positions[i]);
    const double twice_area = normal.norm();
    if (!(twice_area > 0.0)) return kNone;
    const Eigen::Vector3d unit = normal / twice_area;
    // Agreement with the corners' mean normal: a hole in a rough layer has
    // corners whose own normals tilt every which way, yet the fill must
    // face the side the surface faces.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int v : {i, k, j}) {
      const double length = normals[v].norm();
      if (!(length > 0.0)) return kNone;
      mean += normals[v] / length;
    }
    if (!(mean.norm() > 0.0)) return kNone;
    const double agreement = unit.dot(mean.normalized());
    if (!(agreement > 0.0) && facing == FillFacing::agree) return kNone;
    return 0.5 * twice_area * (2.0 - agreement);
  };
  for (int span = 2; span < n; ++span)
    for (int i = 0; i + span < n; ++i) {
      const int j = i + span;
      if (!allowed[at(i, j)]) continue;
      double best = kNone;
      int best_k = -1;
      for (int k = i + 1; k < j; ++k) {
        const double sides = cost[at(i, k)] + cost[at(k, j)];
        if (!(sides < kNone)) continue;
        const double total = sides + weight(i, k, j);
        if (total < best) {
          best = total;
          best_k = k;
        }
      }
      cost[at(i, j)] = best;
      split[at(i, j)] = best_k;
    }
  if (!(cost[at(0, n - 1)] < kNone)) return result;
  std::vector<std::pair<int, int>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2) continue;
    const int k = split[at(i, j)];
    result.triangles.push_back({i, k, j});
    stack.emplace_back(i, k);
    stack.emplace_back(k, j);
  }
  result.found = true;
  return result;
}

}  // namespace icrkit::reconstruction
