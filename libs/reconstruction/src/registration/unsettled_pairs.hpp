#pragma once
// Which pairs of a multiway round the round's own pose graph has made stale
// (SequenceRegistrationParameters::max_unsettled_rounds): a pair the ICP
// could not reach, between views no accepted pair links, whose views the
// graph then moved relative to each other beyond the ICP's reach.

#include <icrkit/reconstruction/registration/scan_sequence_registration.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <optional>
#include <vector>

namespace icrkit::reconstruction {

/// Indices of `pairs` rejected with an ICP inlier fraction below
/// `min_inlier_fraction` (0 also where the ICP did not run), between two
/// groups of views the accepted `pairs` link (`linkedViews`), whose view
/// `to` (its points' centroid, `centroids[to]`; views without one are
/// skipped) sits more than `move` metres elsewhere in view `from`'s frame
/// at the poses `after` than at `before`.
std::vector<std::size_t> unsettledPairs(const std::vector<PairRegistrationRecord>& pairs,
                                        const std::vector<Eigen::Isometry3d>& before,
                                        const std::vector<Eigen::Isometry3d>& after,
                                        const std::vector<std::optional<Eigen::Vector3d>>& centroids,
                                        double min_inlier_fraction, double move);

}  // namespace icrkit::reconstruction
