#include <icrkit/planning/placement_score.hpp>

#include <icrkit/core/error.hpp>

#include <algorithm>
#include <limits>
#include <cmath>
#include <random>
#include <string>

namespace icrkit::planning {

void PlacementParameters::validate() const {
  if (!(std::isfinite(placement_error_m) && placement_error_m >= 0.0))
    throw InputError("PlacementParameters::placement_error_m", "",
                     "expected a finite error >= 0 (metres), got " + std::to_string(placement_error_m));
  if (samples < 1) throw InputError("PlacementParameters::samples", "", "expected at least 1 sample");
}

void tangentBasis(const Eigen::Vector3d& normal, Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  // The axis least aligned with the normal gives a well-conditioned cross product.
  const Eigen::Vector3d helper = std::abs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  t1 = normal.cross(helper).normalized();
  t2 = normal.cross(t1);
}

PlacementScorer::PlacementScorer(const icr::GraspableObject& object, const PlacementParameters& params)
    : object_(object), params_(params) {
  params_.validate();
  for (std::size_t v = 0; v < object.vertexCount(); ++v)
    if (object.referenced(v)) {
      surface_.push_back(object.position(v));
      surface_index_.push_back(static_cast<int>(v));
    }
  tree_ = std::make_unique<KdTree>(surface_);
  // A fixed seed: the offsets are part of the score's definition, not of the plan's randomness.
  std::mt19937_64 random(0x5eedULL);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  offsets_.resize(params_.placement_error_m > 0.0 ? params_.samples : 1, Eigen::Vector2d::Zero());
  if (params_.placement_error_m > 0.0)
    for (Eigen::Vector2d& o : offsets_) {
      const double x = gaussian(random), y = gaussian(random);
      o = params_.placement_error_m * Eigen::Vector2d(x, y);
    }
}

PlacementScorer::~PlacementScorer() = default;

int PlacementScorer::landing(const Eigen::Vector3d& aim, const Eigen::Vector3d& normal,
                             const Eigen::Vector2d& offset) const {
  if (surface_.empty()) return -1;
  Eigen::Vector3d t1, t2;
  tangentBasis(normal, t1, t2);
  const Eigen::Vector3d target = aim + offset.x() * t1 + offset.y() * t2;
  // A thin wall's other side can be nearer than the side the finger faces.
  constexpr std::size_t kClosest = 8;
  const std::vector<Neighbour> near = tree_->nearest(target, kClosest);
  for (const Neighbour& n : near) {
    const int v = surface_index_[n.index];
    if (object_.normal(static_cast<std::size_t>(v)).dot(normal) > 0.0) return v;
  }
  return surface_index_[near.front().index];
}

PlacementScore PlacementScorer::score(const icr::IcrResult& regions) const {
  PlacementScore s;
  s.probability = 1.0;
  s.min_depth_m = std::numeric_limits<double>::infinity();
  for (const icr::ContactRegion& region : regions.regions) {
    double p = 0.0;
    if (region.recommended.vertex >= 0) {
      const auto aim = static_cast<std::size_t>(region.recommended.vertex);
      std::size_t inside = 0;
      for (const Eigen::Vector2d& o : offsets_) {
        const int v = landing(object_.position(aim), object_.normal(aim), o);
        if (std::binary_search(region.vertices.begin(), region.vertices.end(), v)) ++inside;
      }
      p = static_cast<double>(inside) / static_cast<double>(offsets_.size());
    }
    s.finger_probability.push_back(p);
    s.probability *= p;
    s.min_depth_m = std::min(s.min_depth_m, region.recommended.vertex >= 0 ? region.recommended.depth_m : 0.0);
  }
  if (regions.regions.empty()) s.probability = 0.0, s.min_depth_m = 0.0;
  return s;
}

}  // namespace icrkit::planning
