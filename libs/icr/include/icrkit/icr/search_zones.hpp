#pragma once
/// \file
/// Search zones: for every GWS hull vertex, the intersection of the exterior
/// half-spaces of its incident facets, each shifted until tangent to the TWS.

#include <icrkit/icr/grasp_wrench_space.hpp>
#include <icrkit/icr/task_wrench_space.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace icrkit::icr {

struct SearchZone {
  int hull_vertex = -1;      ///< input wrench index
  std::vector<int> facets;   ///< indices into SearchZones::normals
};

struct SearchZones {
  WrenchSet normals;               ///< outward unit facet normals
  std::vector<double> thresholds;  ///< a wrench w is beyond facet f when normals.col(f) . w >= thresholds[f]
  std::vector<std::vector<SearchZone>> by_finger;  ///< the zones each finger owns
  std::vector<std::vector<int>> finger_facets;     ///< per finger, every facet its zones use (ascending)
};

/// `wrenches_per_contact` maps wrench index k to finger k / wrenches_per_contact.
SearchZones computeSearchZones(const GraspWrenchSpace& gws, const TaskWrenchSpace& tws, std::size_t finger_count,
                               std::size_t wrenches_per_contact);

/// The same, for fingers that contribute different numbers of wrenches
/// (patch contacts): wrench k belongs to finger `finger_of_wrench[k]`
/// (< finger_count), one entry per wrench the hull was built from.
SearchZones computeSearchZones(const GraspWrenchSpace& gws, const TaskWrenchSpace& tws, std::size_t finger_count,
                               const std::vector<int>& finger_of_wrench);

/// One finger's zones as the zone tests read them: one row per facet its
/// zones use (row-major, so that a facet's normal is one contiguous 48-byte
/// read), its threshold, and per zone the rows of its facets.
struct FingerFacetRows {
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> normals;
  Eigen::VectorXd thresholds;
  std::vector<std::vector<int>> zone_rows;

  /// Whether the wrench `w` (6 values) lies at least `required` beyond every
  /// facet of `zone`; with `slack`, its smallest margin there when it does.
  /// A facet that rejects a wrench moves to the front of its zone, where it
  /// will likely reject the next one too: only the order of the work
  /// changes, never the answer.
  bool holds(std::size_t zone, const double* w, double required = 0.0, double* slack = nullptr) {
    std::vector<int>& rows = zone_rows[zone];
    double smallest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const int r = rows[k];
      const double* n = normals.data() + 6 * r;
      const double margin =
          n[0] * w[0] + n[1] * w[1] + n[2] * w[2] + n[3] * w[3] + n[4] * w[4] + n[5] * w[5] - thresholds(r);
      if (margin < required) {
        if (k > 0) std::swap(rows[k], rows[0]);
        return false;
      }
      smallest = std::min(smallest, margin);
    }
    if (slack) *slack = smallest;
    return true;
  }
};

/// Per finger, its rows (FingerFacetRows).
std::vector<FingerFacetRows> fingerFacetRows(const SearchZones& zones);

/// Tests candidate contacts against the zones, stopping at the first facet
/// that rejects a wrench, so a candidate that fails its first zone costs a
/// handful of dot products. (Remembering products shared by zones of one
/// finger was slower than recomputing them: a 6-D dot product over
/// contiguous rows costs less than the bookkeeping.) Not thread-safe: the
/// tester reorders its work as it goes; use one tester per thread.
class ZoneTester {
public:
  explicit ZoneTester(const SearchZones& zones);

  /// True when every zone of `finger` holds at least one column of `wrenches`.
  bool qualifies(std::size_t finger, const WrenchSet& wrenches);
  /// The same with every facet's threshold raised by `required` >= 0: the
  /// held wrench lies at least that far beyond each facet of the zone
  /// (conservative growth, conservative_growth.hpp).
  bool qualifies(std::size_t finger, const WrenchSet& wrenches, double required);

  /// Why a candidate that qualified passed each zone of its finger: per
  /// zone, the wrench (column) that held it and a lower bound on that
  /// wrench's smallest margin n . w - threshold over the zone's facets.
  struct Evidence {
    const WrenchSet* wrenches = nullptr;
    const Eigen::Index* wrench = nullptr;  ///< zoneCount(finger) entries
    const double* slack = nullptr;         ///< zoneCount(finger) entries
  };
  std::size_t zoneCount(std::size_t finger) const { return fingers_[finger].rows.zone_rows.size(); }

  /// The same answer, sped up by a neighbour's evidence: the facet normals
  /// are unit, so a wrench that moved by less than its slack from one that
  /// held a zone still holds it, and the zone's facets are not evaluated
  /// (a margin of 1e-12 times the largest wrench component is given up per
  /// hop for rounding). On a fine mesh neighbouring
  /// vertices' wrenches differ little and most zone tests end there. When
  /// the candidate qualifies, its own evidence is written to
  /// `wrench_out` / `slack_out` (zoneCount(finger) entries each).
  /// Evidence slacks are raw margins (before `required` is taken off), so
  /// neighbours with different requirements share them.
  bool qualifies(std::size_t finger, const WrenchSet& wrenches, const Evidence* neighbour, Eigen::Index* wrench_out,
                 double* slack_out, double required = 0.0);
  /// How many zone tests a neighbour's evidence settled so far.
  std::size_t zonesOnEvidence() const { return zones_on_evidence_; }

private:
  struct FingerFacets {
    FingerFacetRows rows;
    // Neighbouring candidates behave alike: each zone first tries the wrench
    // that held it last time. Only the order of the work changes.
    std::vector<Eigen::Index> last_wrench;
  };

  std::vector<FingerFacets> fingers_;
  std::size_t zones_on_evidence_ = 0;
};

}  // namespace icrkit::icr
