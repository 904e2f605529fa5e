#include <icrkit/icr/search_zones.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace icrkit::icr {

SearchZones computeSearchZones(const GraspWrenchSpace& gws, const TaskWrenchSpace& tws, std::size_t finger_count,
                               std::size_t wrenches_per_contact) {
  std::vector<int> finger_of_wrench(finger_count * wrenches_per_contact);
  for (std::size_t k = 0; k < finger_of_wrench.size(); ++k) finger_of_wrench[k] = static_cast<int>(k / wrenches_per_contact);
  return computeSearchZones(gws, tws, finger_count, finger_of_wrench);
}

SearchZones computeSearchZones(const GraspWrenchSpace& gws, const TaskWrenchSpace& tws, std::size_t finger_count,
                               const std::vector<int>& finger_of_wrench) {
  SearchZones zones;
  zones.normals = gws.normals;
  const std::size_t facet_count = gws.facetCount();
  zones.thresholds.resize(facet_count);
  for (std::size_t f = 0; f < facet_count; ++f)
    zones.thresholds[f] = tws.support(gws.normals.col(static_cast<Eigen::Index>(f)));

  // Hull vertex -> incident facets, by inverting the facet -> vertex lists.
  std::vector<std::vector<int>> incident(finger_of_wrench.size());
  for (std::size_t f = 0; f < facet_count; ++f)
    for (int v : gws.facet_vertices[f])
      if (static_cast<std::size_t>(v) < incident.size()) incident[static_cast<std::size_t>(v)].push_back(static_cast<int>(f));

  zones.by_finger.assign(finger_count, {});
  zones.finger_facets.assign(finger_count, {});
  // A facet is listed once per finger however many of its zones use it; the
  // marks keep the lists ascending without sorting.
  std::vector<std::uint8_t> used_by(facet_count * finger_count, 0);
  for (int v : gws.hull_vertices) {
    if (static_cast<std::size_t>(v) >= finger_of_wrench.size()) continue;
    const int finger = finger_of_wrench[static_cast<std::size_t>(v)];
    if (finger < 0 || static_cast<std::size_t>(finger) >= finger_count || incident[static_cast<std::size_t>(v)].empty())
      continue;
    SearchZone zone;
    zone.hull_vertex = v;
    zone.facets = std::move(incident[static_cast<std::size_t>(v)]);
    for (int f : zone.facets) used_by[static_cast<std::size_t>(f) * finger_count + static_cast<std::size_t>(finger)] = 1;
    zones.by_finger[static_cast<std::size_t>(finger)].push_back(std::move(zone));
  }
  for (std::size_t f = 0; f < facet_count; ++f)
    for (std::size_t finger = 0; finger < finger_count; ++finger)
      if (used_by[f * finger_count + finger]) zones.finger_facets[finger].push_back(static_cast<int>(f));
  return zones;
}

std::vector<FingerFacetRows> fingerFacetRows(const SearchZones& zones) {
  std::vector<FingerFacetRows> fingers(zones.by_finger.size());
  std::vector<int> row_of(zones.thresholds.size(), -1);
  for (std::size_t finger = 0; finger < zones.by_finger.size(); ++finger) {
    const std::vector<int>& facets = zones.finger_facets[finger];
    FingerFacetRows& local = fingers[finger];
    local.normals.resize(static_cast<Eigen::Index>(facets.size()), 6);
    local.thresholds.resize(static_cast<Eigen::Index>(facets.size()));
    for (std::size_t r = 0; r < facets.size(); ++r) {
      local.normals.row(static_cast<Eigen::Index>(r)) = zones.normals.col(facets[r]).transpose();
      local.thresholds(static_cast<Eigen::Index>(r)) = zones.thresholds[static_cast<std::size_t>(facets[r])];
      row_of[static_cast<std::size_t>(facets[r])] = static_cast<int>(r);
    }
    for (const SearchZone& zone : zones.by_finger[finger]) {
      std::vector<int> rows(zone.facets.size());
      for (std::size_t k = 0; k < zone.facets.size(); ++k) rows[k] = row_of[static_cast<std::size_t>(zone.facets[k])];
      local.zone_rows.push_back(std::move(rows));
    }
  }
  return fingers;
}

ZoneTester::ZoneTester(const SearchZones& zones) {
  for (FingerFacetRows& rows : fingerFacetRows(zones)) {
    FingerFacets local;
    local.last_wrench.assign(rows.zone_rows.size(), 0);
    local.rows = std::move(rows);
    fingers_.push_back(std::move(local));
  }
}

bool ZoneTester::qualifies(std::size_t finger, const WrenchSet& wrenches) {
  return qualifies(finger, wrenches, nullptr, nullptr, nullptr, 0.0);
}

bool ZoneTester::qualifies(std::size_t finger, const WrenchSet& wrenches, double required) {
  return qualifies(finger, wrenches, nullptr, nullptr, nullptr, required);
}

bool ZoneTester::qualifies(std::size_t finger, const WrenchSet& wrenches, const Evidence* neighbour,
                           Eigen::Index* wrench_out, double* slack_out, double required) {
  FingerFacets& local = fingers_[finger];
  const Eigen::Index n = wrenches.cols();
  const bool comparable = neighbour && neighbour->wrenches && neighbour->wrenches->cols() == n;
  // Products of O(|w|) terms carry rounding of about 1e-16 |w|; every hop
  // gives up a margin far above that, so a chain of shortcuts stays sound.
  const double margin = comparable ? 1e-12 * std::max(1.0, wrenches.cwiseAbs().maxCoeff()) : 0.0;
  for (std::size_t z = 0; z < local.rows.zone_rows.size(); ++z) {
    if (comparable) {
      const Eigen::Index w = neighbour->wrench[z];
      const double moved = (wrenches.col(w) - neighbour->wrenches->col(w)).norm();
      const double left = neighbour->slack[z] - moved - margin;
      if (left > required) {
        ++zones_on_evidence_;
        if (wrench_out) {
          wrench_out[z] = w;
          slack_out[z] = left;
        }
        continue;
      }
    }
    const Eigen::Index first = local.last_wrench[z] < n ? local.last_wrench[z] : 0;
    double slack = 0.0;
    Eigen::Index held = local.rows.holds(z, wrenches.data() + 6 * first, required, &slack) ? first : -1;
    for (Eigen::Index w = 0; w < n && held < 0; ++w) {
      if (w == first) continue;
      if (local.rows.holds(z, wrenches.data() + 6 * w, required, &slack)) {
        held = w;
        local.last_wrench[z] = w;
      }
    }
    if (held < 0) return false;
    if (wrench_out) {
      wrench_out[z] = held;
      slack_out[z] = slack;
    }
  }
  return true;
}

}  // namespace icrkit::icr
