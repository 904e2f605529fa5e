#include <icrkit/core/point_cloud.hpp>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace icrkit {

bool PointCloud::flag(const std::string& name, std::size_t index) const {
  const Attribute* a = attributes.find(name);
  return a != nullptr && a->values.at(index) != 0.0;
}

void PointCloud::setFlag(const std::string& name, std::size_t index, bool value) {
  Attribute* a = attributes.find(name);
  if (a == nullptr) a = &attributes.add(name, ScalarType::UInt8, size(), 0.0);
  a->values.at(index) = value ? 1.0 : 0.0;
}

void PointCloud::resize(std::size_t count) {
  positions.resize(count, Eigen::Vector3d::Zero());
  if (hasNormals()) normals.resize(count, Eigen::Vector3d::Zero());
  if (hasColours()) colours.resize(count, Colour{0, 0, 0});
  attributes.resize(count);
}

void PointCloud::select(const std::vector<std::size_t>& indices) {
  auto pick = [&](auto& array) {
    if (array.empty()) return;
    std::decay_t<decltype(array)> kept;
    kept.reserve(indices.size());
    for (std::size_t i : indices) kept.push_back(array.at(i));
    array = std::move(kept);
  };
  pick(positions);
  pick(normals);
  pick(colours);
  attributes.select(indices);
}

void PointCloud::append(const PointCloud& other) {
  if (other.empty()) return;
  if (empty()) {
    *this = other;
    return;
  }
  if (hasNormals() != other.hasNormals() || hasColours() != other.hasColours() ||
      attributes.size() != other.attributes.size())
    throw std::invalid_argument("PointCloud::append: the clouds carry different per-point data");
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  colours.insert(colours.end(), other.colours.begin(), other.colours.end());
  for (Attribute& a : attributes) {
    const Attribute* b = other.attributes.find(a.name);
    if (b == nullptr)
      throw std::invalid_argument("PointCloud::append: the other cloud has no attribute '" + a.name + "'");
    a.values.insert(a.values.end(), b->values.begin(), b->values.end());
  }
}

void PointCloud::validate() const {
  const std::size_t n = size();
  if (!normals.empty() && normals.size() != n)
    throw std::invalid_argument("point cloud has " + std::to_string(normals.size()) + " normals for " +
                                std::to_string(n) + " points");
  if (!colours.empty() && colours.size() != n)
    throw std::invalid_argument("point cloud has " + std::to_string(colours.size()) + " colours for " +
                                std::to_string(n) + " points");
  for (const Attribute& a : attributes)
    if (a.values.size() != n)
      throw std::invalid_argument("attribute '" + a.name + "' has " + std::to_string(a.values.size()) +
                                  " values for " + std::to_string(n) + " points");
  for (std::size_t i = 0; i < n; ++i)
    if (!positions[i].allFinite())
      throw std::invalid_argument("point " + std::to_string(i) + " has a non-finite coordinate");
}

Eigen::AlignedBox3d PointCloud::bounds() const {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : positions) box.extend(p);
  return box;
}

}  // namespace icrkit
