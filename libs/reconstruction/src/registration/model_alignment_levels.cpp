#include "model_alignment_levels.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace icrkit::reconstruction {

double largestSpread(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) return 0.0;
  // Two passes (mean, then deviations): a view sits a metre from its
  // camera and millimetres matter, where sum x x^T - n m m^T cancels.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) sum += p;
  const Eigen::Vector3d mean = sum / double(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter.noalias() += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter / double(points.size()),
                                                              Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(solver.eigenvalues()(2), 0.0));
}

double medianViewSpread(const std::vector<const std::vector<Eigen::Vector3d>*>& views) {
  std::vector<double> spreads;
  for (const std::vector<Eigen::Vector3d>* v : views)
    if (v->size() >= 2) spreads.push_back(largestSpread(*v));
  if (spreads.empty()) return 0.0;
  std::sort(spreads.begin(), spreads.end());
  const std::size_t m = spreads.size() / 2;
  return spreads.size() % 2 ? spreads[m] : 0.5 * (spreads[m - 1] + spreads[m]);
}

std::vector<double> modelAlignmentLevels(const std::vector<double>& resolutions, double max_cell_to_spread,
                                         double spread) {
  if (resolutions.empty() || max_cell_to_spread <= 0 || !(spread > 0)) return resolutions;
  std::vector<double> kept;
  for (std::size_t l = 0; l + 1 < resolutions.size(); ++l)
    if (resolutions[l] <= max_cell_to_spread * spread) kept.push_back(resolutions[l]);
  kept.push_back(resolutions.back());
  return kept;
}

}  // namespace icrkit::reconstruction
