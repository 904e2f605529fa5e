#include <icrkit/core/kd_tree.hpp>

// Ties in k-nearest queries then come out lowest index first, so results do
// not depend on how the tree happened to split equal coordinates.
#define NANOFLANN_FIRST_MATCH
#include <nanoflann.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace icrkit {
namespace {

// nanoflann reads points through this adaptor so the caller's vector is used
// in place, never copied.
struct PointsAdaptor {
  const std::vector<Eigen::Vector3d>* points;

  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const { return (*points)[index][static_cast<int>(dim)]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>, PointsAdaptor,
                                                  3, std::size_t>;

// nanoflann's own RadiusResultSet keeps only dist < r^2 and its leaf loop
// tests dist < worstDist(); our API promises distance <= radius, so the
// bound handed to the search is the next double above r^2 and the set
// itself tests <=.
class InclusiveRadiusSet {
public:
  InclusiveRadiusSet(double radius_sq, std::vector<std::pair<std::size_t, double>>* found)
      : radius_sq_(radius_sq), bound_(std::nextafter(radius_sq, std::numeric_limits<double>::infinity())),
        found_(found) {}

  std::size_t size() const { return count_; }
  bool full() const { return true; }
  double worstDist() const { return bound_; }
  bool addPoint(double dist_sq, std::size_t index) {
    if (dist_sq <= radius_sq_) {
      ++count_;
      if (found_) found_->emplace_back(index, dist_sq);
      if (indices_) indices_->push_back(index);
    }
    return true;
  }
  void collectIndices(std::vector<std::size_t>* indices) { indices_ = indices; }

private:
  double radius_sq_;
  double bound_;
  std::vector<std::pair<std::size_t, double>>* found_;  // null: only count
  std::vector<std::size_t>* indices_ = nullptr;
  std::size_t count_ = 0;
};

// The single nearest point under a distance bound.
class NearestWithinSet {
public:
  explicit NearestWithinSet(double bound_sq) : best_sq_(bound_sq) {}
  std::size_t size() const { return found_ ? 1 : 0; }
  bool full() const { return true; }
  // Once a point is found, one ulp beyond its distance: a point as near in
  // another leaf still reaches addPoint (nanoflann admits only points
  // strictly nearer than this), so ties go to the lowest index whatever
  // the tree's shape.
  double worstDist() const {
    return found_ ? std::nextafter(best_sq_, std::numeric_limits<double>::infinity()) : best_sq_;
  }
  bool addPoint(double dist_sq, std::size_t index) {
    if (dist_sq < best_sq_ || (found_ && dist_sq == best_sq_ && index < index_)) {
      best_sq_ = dist_sq;
      index_ = index;
      found_ = true;
    }
    return true;
  }
  long index() const { return found_ ? static_cast<long>(index_) : -1; }

private:
  double best_sq_;
  std::size_t index_ = 0;
  bool found_ = false;
};

}  // namespace

struct KdTree::Impl {
  PointsAdaptor adaptor;
  Index index;

  Impl(const std::vector<Eigen::Vector3d>& points, std::size_t leaf_size)
      : adaptor{&points}, index(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(leaf_size)) {}

  std::size_t radiusSearch(const Eigen::Vector3d& query, double radius,
                           std::vector<std::pair<std::size_t, double>>* found,
                           std::vector<std::size_t>* indices = nullptr) const {
    if (!(radius >= 0.0) || adaptor.points->empty()) return 0;  // also rejects NaN
    InclusiveRadiusSet set(radius * radius, found);
    set.collectIndices(indices);
    index.findNeighbors(set, query.data(), nanoflann::SearchParams());
    return set.size();
  }
};

KdTree::KdTree(const std::vector<Eigen::Vector3d>& points, std::size_t leaf_size)
    : impl_(std::make_unique<Impl>(points, std::max<std::size_t>(leaf_size, 1))) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

std::size_t KdTree::size() const { return impl_->adaptor.points->size(); }

std::vector<Neighbour> KdTree::nearest(const Eigen::Vector3d& query, std::size_t k) const {
  k = std::min(k, size());
  if (k == 0) return {};
  std::vector<std::size_t> indices(k);
  std::vector<double> dist_sq(k);
  const std::size_t n = impl_->index.knnSearch(query.data(), k, indices.data(), dist_sq.data());
  std::vector<Neighbour> result(n);
  for (std::size_t i = 0; i < n; ++i) result[i] = {indices[i], std::sqrt(dist_sq[i])};
  return result;
}

std::vector<Neighbour> KdTree::withinRadius(const Eigen::Vector3d& query, double radius) const {
  std::vector<std::pair<std::size_t, double>> found;
  impl_->radiusSearch(query, radius, &found);
  // Index as the tie-breaker keeps the order independent of the tree layout.
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
    return a.second < b.second || (a.second == b.second && a.first < b.first);
  });
  std::vector<Neighbour> result(found.size());
  for (std::size_t i = 0; i < found.size(); ++i) result[i] = {found[i].first, std::sqrt(found[i].second)};
  return result;
}

void KdTree::indicesWithinRadius(const Eigen::Vector3d& query, double radius, std::vector<std::size_t>& out) const {
  out.clear();
  impl_->radiusSearch(query, radius, nullptr, &out);
  // Ascending index: a canonical order, so sums over the neighbours do not
  // depend on how the tree happened to be split.
  std::sort(out.begin(), out.end());
}

void KdTree::indicesWithinRadiusInTreeOrder(const Eigen::Vector3d& query, double radius,
                                            std::vector<std::size_t>& out) const {
  out.clear();
  impl_->radiusSearch(query, radius, nullptr, &out);
}

long KdTree::nearestWithin(const Eigen::Vector3d& query, double max_distance) const {
  if (!(max_distance > 0.0) || impl_->adaptor.points->empty()) return -1;  // also rejects NaN
  NearestWithinSet set(max_distance * max_distance);
  impl_->index.findNeighbors(set, query.data(), nanoflann::SearchParams());
  return set.index();
}

std::size_t KdTree::countWithinRadius(const Eigen::Vector3d& query, double radius) const {
  return impl_->radiusSearch(query, radius, nullptr);
}

std::vector<double> nearestNeighbourDistances(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) return std::vector<double>(points.size(), std::numeric_limits<double>::infinity());
  return nearestNeighbourDistances(points, KdTree(points));
}

std::vector<double> nearestNeighbourDistances(const std::vector<Eigen::Vector3d>& points, const KdTree& tree) {
  const std::size_t n = points.size();
  std::vector<double> spacing(n, std::numeric_limits<double>::infinity());
  if (n < 2) return spacing;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      // Two neighbours suffice: the point itself is one of them unless
      // duplicates crowd it out, in which case the other one is at 0 anyway.
      double best = std::numeric_limits<double>::infinity();
      for (const Neighbour& nb : tree.nearest(points[i], 2))
        if (nb.index != i) best = std::min(best, nb.distance);
      spacing[i] = best;
    }
  });
  return spacing;
}

SpacingStatistics spacingStatistics(std::vector<double> spacing) {
  SpacingStatistics stats;
  const std::size_t n = spacing.size();
  if (n < 2) return stats;
  // Summed serially in index order: the same bits whatever the thread count.
  double sum = 0.0;
  for (double d : spacing) sum += d;
  stats.mean = sum / static_cast<double>(n);

  const std::size_t mid = n / 2;
  std::nth_element(spacing.begin(), spacing.begin() + static_cast<std::ptrdiff_t>(mid), spacing.end());
  const double upper = spacing[mid];
  if (n % 2 == 1) {
    stats.median = upper;
  } else {
    const double lower = *std::max_element(spacing.begin(), spacing.begin() + static_cast<std::ptrdiff_t>(mid));
    stats.median = 0.5 * (lower + upper);
  }
  return stats;
}

SpacingStatistics nearestNeighbourSpacing(const std::vector<Eigen::Vector3d>& points) {
  return spacingStatistics(nearestNeighbourDistances(points));
}

}  // namespace icrkit
