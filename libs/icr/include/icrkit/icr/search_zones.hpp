#pragma once
/// \file
/// Search zones: for every GWS hull vertex, the intersection of the exterior
/// half-spaces of its incident facets, each shifted until tangent to the TWS.

#include <icrkit/icr/grasp_wrench_space.hpp>
#include <icrkit/icr/task_wrench_space.hpp>

#include <cstdint>
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
  std::size_t zoneCount(std::size_t finger) const { return fingers_[finger].zone_rows.size(); }

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
    // One row per facet the finger's zones use; row-major, so that a facet's
    // normal is one contiguous 48-byte read.
    Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> normals;
    Eigen::VectorXd thresholds;
    std::vector<std::vector<int>> zone_rows;  // per zone, rows of `normals`
    // Neighbouring candidates behave alike: each zone first tries the wrench
    // that held it last time, and a facet that rejects a wrench moves to the
    // front of its zone. Only the order of the work changes, never the answer.
    std::vector<Eigen::Index> last_wrench;
  };
  // With `slack`, a wrench that holds the zone gets its smallest margin there.
  bool holds(FingerFacets& local, std::size_t zone, Eigen::Index wrench, const WrenchSet& wrenches, double required,
             double* slack = nullptr);

  std::vector<FingerFacets> fingers_;
  std::size_t zones_on_evidence_ = 0;
};

}  // namespace icrkit::icr
