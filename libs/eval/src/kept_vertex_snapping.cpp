#include <icrkit/eval/kept_vertex_snapping.hpp>

#include <icrkit/core/error.hpp>

#include <charconv>
#include <cmath>

namespace icrkit::eval {
namespace {

constexpr const char* kSource = "kept-vertex snapping";

double checkedRadius(double radius_m) {
  if (!std::isfinite(radius_m) || !(radius_m > 0.0))
    throw InputError(kSource, "radius", "expected a finite length > 0 (metres), got " + std::to_string(radius_m));
  return radius_m;
}

// std::to_chars does not follow LC_NUMERIC, so the reasons recorded in
// grasps.jsonl read the same on every machine.
std::string millimetres(double metres) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), metres * 1e3, std::chars_format::fixed, 3);
  return std::string(buffer, result.ptr) + " mm";
}

std::string contactName(std::size_t k) { return "contact " + std::to_string(k); }

}  // namespace

KeptVertexSnapping::KeptVertexSnapping(const icr::GraspableObject& object, double radius_m)
    : object_(&object),
      radius_(checkedRadius(radius_m)),
      kept_vertices_([&] {
        std::vector<int> kept;
        for (std::size_t v = 0; v < object.vertexCount(); ++v)
          if (object.eligible(v)) kept.push_back(static_cast<int>(v));
        return kept;
      }()),
      kept_positions_([&] {
        std::vector<Eigen::Vector3d> positions;
        positions.reserve(kept_vertices_.size());
        for (const int v : kept_vertices_) positions.push_back(object.position(static_cast<std::size_t>(v)));
        return positions;
      }()),
      kept_tree_(kept_positions_) {}

SnappedContacts KeptVertexSnapping::snap(const std::vector<int>& contacts) const {
  SnappedContacts result;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const int vertex = contacts[k];
    if (vertex < 0 || static_cast<std::size_t>(vertex) >= object_->vertexCount())
      throw InputError(kSource, contactName(k),
                       "vertex " + std::to_string(vertex) + " is out of range for " +
                           std::to_string(object_->vertexCount()) + " vertices");
    if (object_->eligible(static_cast<std::size_t>(vertex))) {
      result.contacts.push_back(vertex);
      result.move_distances_m.push_back(0.0);
      continue;
    }
    // Sorted by distance, then by the tree's index: the first is the
    // nearest kept vertex, the lower index among equally near ones.
    const std::vector<Neighbour> near =
        kept_tree_.withinRadius(object_->position(static_cast<std::size_t>(vertex)), radius_);
    if (near.empty()) {
      result.contacts.clear();
      result.move_distances_m.clear();
      result.reason = contactName(k) + ": no kept vertex within " + millimetres(radius_) + " of excluded vertex " +
                      std::to_string(vertex);
      return result;
    }
    result.contacts.push_back(kept_vertices_[near.front().index]);
    result.move_distances_m.push_back(near.front().distance);
  }
  for (std::size_t k = 0; k < result.contacts.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (result.contacts[k] == result.contacts[j]) {
        result.reason = contactName(j) + " and " + contactName(k) + " end on the same vertex after snapping";
        return result;
      }
  return result;
}

}  // namespace icrkit::eval
