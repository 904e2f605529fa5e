#include <icrkit/icr/search_zones.hpp>

#include <algorithm>

namespace icrkit::icr {

SearchZones computeSearchZones(const GraspWrenchSpace& gws, const TaskWrenchSpace& tws, std::size_t finger_count,
                               std::size_t wrenches_per_contact) {
  SearchZones zones;
  zones.normals = gws.normals;
  const std::size_t facet_count = gws.facetCount();
  zones.thresholds.resize(facet_count);
  for (std::size_t f = 0; f < facet_count; ++f)
    zones.thresholds[f] = tws.support(gws.normals.col(static_cast<Eigen::Index>(f)));

  // Hull vertex -> incident facets, by inverting the facet -> vertex lists.
  std::vector<std::vector<int>> incident(finger_count * wrenches_per_contact);
  for (std::size_t f = 0; f < facet_count; ++f)
    for (int v : gws.facet_vertices[f]) incident[static_cast<std::size_t>(v)].push_back(static_cast<int>(f));

  zones.by_finger.assign(finger_count, {});
  zones.finger_facets.assign(finger_count, {});
  for (int v : gws.hull_vertices) {
    const std::size_t finger = static_cast<std::size_t>(v) / wrenches_per_contact;
    if (finger >= finger_count || incident[static_cast<std::size_t>(v)].empty()) continue;
    SearchZone zone;
    zone.hull_vertex = v;
    zone.facets = incident[static_cast<std::size_t>(v)];
    auto& used = zones.finger_facets[finger];
    used.insert(used.end(), zone.facets.begin(), zone.facets.end());
    zones.by_finger[finger].push_back(std::move(zone));
  }
  for (auto& used : zones.finger_facets) {
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
  }
  return zones;
}

ZoneTester::ZoneTester(const SearchZones& zones) {
  fingers_.resize(zones.by_finger.size());
  for (std::size_t finger = 0; finger < zones.by_finger.size(); ++finger) {
    const std::vector<int>& facets = zones.finger_facets[finger];
    FingerFacets& local = fingers_[finger];
    local.normals.resize(static_cast<Eigen::Index>(facets.size()), 6);
    local.thresholds.resize(static_cast<Eigen::Index>(facets.size()));
    for (std::size_t r = 0; r < facets.size(); ++r) {
      local.normals.row(static_cast<Eigen::Index>(r)) = zones.normals.col(facets[r]).transpose();
      local.thresholds(static_cast<Eigen::Index>(r)) = zones.thresholds[static_cast<std::size_t>(facets[r])];
    }
    for (const SearchZone& zone : zones.by_finger[finger]) {
      std::vector<int> rows;
      for (int f : zone.facets)
        rows.push_back(static_cast<int>(std::lower_bound(facets.begin(), facets.end(), f) - facets.begin()));
      local.zone_rows.push_back(std::move(rows));
    }
    local.last_wrench.assign(local.zone_rows.size(), 0);
  }
}

double ZoneTester::product(const FingerFacets& local, int row, Eigen::Index wrench, const WrenchSet& wrenches) {
  const std::size_t slot = static_cast<std::size_t>(row) * static_cast<std::size_t>(wrenches.cols()) +
                           static_cast<std::size_t>(wrench);
  if (stamp_[slot] != generation_) {
    stamp_[slot] = generation_;
    products_[slot] = local.normals.row(row).dot(wrenches.col(wrench));
  }
  return products_[slot];
}

bool ZoneTester::holds(FingerFacets& local, std::size_t zone, Eigen::Index wrench, const WrenchSet& wrenches) {
  std::vector<int>& rows = local.zone_rows[zone];
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const int r = rows[k];
    if (product(local, r, wrench, wrenches) < local.thresholds(r)) {
      if (k > 0) std::swap(rows[k], rows[0]);
      return false;
    }
  }
  return true;
}

bool ZoneTester::qualifies(std::size_t finger, const WrenchSet& wrenches) {
  FingerFacets& local = fingers_[finger];
  const Eigen::Index n = wrenches.cols();
  const std::size_t slots = static_cast<std::size_t>(local.normals.rows()) * static_cast<std::size_t>(n);
  if (stamp_.size() < slots) {
    stamp_.assign(slots, 0);
    products_.resize(slots);
    generation_ = 0;
  }
  if (++generation_ == 0) {  // wrapped: forget every stamp
    std::fill(stamp_.begin(), stamp_.end(), 0);
    generation_ = 1;
  }
  for (std::size_t z = 0; z < local.zone_rows.size(); ++z) {
    const Eigen::Index first = local.last_wrench[z] < n ? local.last_wrench[z] : 0;
    bool held = holds(local, z, first, wrenches);
    for (Eigen::Index w = 0; w < n && !held; ++w) {
      if (w == first) continue;
      if (holds(local, z, w, wrenches)) {
        held = true;
        local.last_wrench[z] = w;
      }
    }
    if (!held) return false;
  }
  return true;
}

}  // namespace icrkit::icr
