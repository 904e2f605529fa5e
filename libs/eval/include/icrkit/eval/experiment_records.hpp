#pragma once
/// \file
/// What the experiment runner measures for one grasp, and the JSON-lines
/// form of it (`grasps.jsonl`) from which every table and figure is computed,
/// so that shards of a study merge by concatenating their records.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::eval {

/// One finger's region on a reconstructed mesh compared with the CAD region.
struct RegionComparison {
  std::size_t vertices = 0;               ///< |C_n^S|
  double area_m2 = 0.0;                   ///< A(C_n^S), on the reconstructed mesh
  double intersection_area_m2 = 0.0;      ///< A(I_n), on the CAD mesh (Algorithm 2)
  double false_positive_area_m2 = 0.0;    ///< see docs/evaluation.md
  /// 100 A(I_n) / A(C_n^C) and 100 FP / A(C_n^C); unset when A(C_n^C) = 0.
  std::optional<double> intersection_percent;
  std::optional<double> false_positive_percent;
  double d1_m = 0.0;                      ///< CAD central point to the CAD region's border
  double d2_m = 0.0;                      ///< mapped central point to that border, negative outside
  std::optional<double> quality;          ///< Q_n = d2 / d1; unset when d1 = 0 (degenerate)
  /// Whether the region's recommended contact (its deepest vertex,
  /// icr/recommended_contact.hpp), mapped onto the CAD mesh by eq. (3),
  /// lies in C_n^C. false for an empty region or a contact that maps
  /// nowhere (no place to aim is not a place inside); unset in records
  /// written before it existed.
  std::optional<bool> recommended_inside;
};

/// Random picks of one vertex per region, moved onto the CAD mesh by eq. (3)
/// and checked there (CAD positions and normals, the grasp's TWS): what a
/// robot that trusts the regions would get on the true object.
struct PickCheck {
  std::size_t tried = 0;     ///< picks drawn (none when a region is empty)
  std::size_t mapped = 0;    ///< picks whose vertices all map onto distinct CAD vertices
  std::size_t held = 0;      ///< mapped picks whose CAD grasp holds the TWS
  /// The one pick a robot would make: every region's recommended contact
  /// (its deepest vertex), moved onto the CAD mesh the same way. Whether
  /// that CAD grasp holds the TWS; false when a contact maps nowhere or two
  /// map onto one CAD vertex. Unset when no picks were drawn (an empty
  /// region) and in records written before it existed.
  std::optional<bool> aimed_held;
};

/// The regions of one mesh grown conservatively (icr/conservative_growth.hpp)
/// with K = `sigmas`, compared with the same CAD regions as the plain ones.
struct ConservativeOutcome {
  double sigmas = 0.0;
  std::vector<RegionComparison> regions;  ///< one per finger; an empty region has 0 vertices and area
  std::optional<PickCheck> picks;
};

/// G^F after its contacts on excluded vertices moved to the nearest kept
/// vertex within the mapping's neighbourhood radius (kept_vertex_snapping.hpp):
/// what a planner would do, not the paper's check, and never used in place of
/// it (no region is grown for a grasp that is eligible only after snapping).
struct SnappedOutcome {
  std::vector<int> contacts;               ///< empty when a contact had no kept vertex within reach
  std::vector<double> move_distances_m;    ///< per contact, how far it moved (0 when it stayed); empty with contacts
  bool task_fulfilled = false;             ///< as MeshOutcome::task_fulfilled, for the snapped contacts
  double epsilon = 0.0;                    ///< of the snapped grasp, 0 when not force closure or not a grasp
  std::string reason;                      ///< why the snapped grasp does not meet the task; empty when it does
};

/// A grasp moved onto one reconstructed mesh (raw or filtered).
struct MeshOutcome {
  std::vector<int> contacts;               ///< by eq. (2); empty when a contact could not be mapped
  bool preselection_passed = true;         ///< no contact on an excluded vertex (filtered mesh only)
  bool task_fulfilled = false;             ///< force closure and the TWS inside its GWS
  double epsilon = 0.0;                    ///< of the mapped grasp, 0 when not force closure
  std::string reason;                      ///< why it is not eligible; empty when it is
  std::vector<RegionComparison> regions;   ///< one per finger, when the grasp was evaluated
  /// ExperimentConfig::picks_per_grasp picks from `regions`, when evaluated
  /// (unset in records written before it existed).
  std::optional<PickCheck> picks;
  /// Filtered mesh only: set when the grasp was mapped but failed the
  /// preselection (ExperimentConfig::snap_excluded_contacts); unset otherwise,
  /// and in records written before it existed (then: not computed).
  std::optional<SnappedOutcome> snapped;
  /// ExperimentConfig::conservative_sigmas, in that order, when the grasp was
  /// evaluated; empty otherwise.
  std::vector<ConservativeOutcome> conservative;

  /// The paper's check: no contact on an excluded vertex, and the task met.
  bool eligible() const { return preselection_passed && task_fulfilled; }
  /// Eligible, or eligible once its contacts snapped to kept vertices (not
  /// the paper's check; false when snapping was not computed).
  bool eligibleAfterSnapping() const { return eligible() || (snapped && snapped->task_fulfilled); }
};

/// One reconstructed mesh's part of the patch-contact study.
struct PatchMeshOutcome {
  bool task_fulfilled = false;            ///< its patch GWS is force closure and holds the patch TWS
  double epsilon = 0.0;                   ///< of its patch GWS, 0 when not force closure
  std::string reason;                     ///< why the task is not met; empty when it is
  std::vector<RegionComparison> regions;  ///< against the CAD patch regions, when the study evaluated the grasp
  /// The grasp of the regions' recommended contacts, moved onto the CAD mesh
  /// by eq. (3), holds the patch TWS with CAD patches there; unset when not
  /// evaluated or a region is empty.
  std::optional<bool> aimed_held;
};

/// The grasp run with multi-point (patch) contacts on all three meshes
/// (ExperimentConfig::patch): its own task (alpha x the CAD patch epsilon)
/// and its own CAD regions. The contacts are the plain record's.
struct PatchRecord {
  double radius_m = 0.0;
  bool filter_border = true;
  double cad_epsilon = 0.0;               ///< of the CAD grasp's patch GWS
  double tws_radius = 0.0;                ///< alpha * cad_epsilon
  std::vector<double> cad_region_areas_m2;  ///< per finger, when evaluated
  PatchMeshOutcome raw, filtered;
  bool evaluated = false;                 ///< both mapped patch grasps hold the task: regions were compared
};

struct GraspRecord {
  std::string dataset;
  std::size_t fingers = 0;
  std::size_t index = 0;                   ///< in the dataset's test set of this finger count
  std::vector<int> cad_contacts;
  double cad_epsilon = 0.0;
  double tws_radius = 0.0;                 ///< alpha * cad_epsilon
  std::vector<double> cad_region_areas_m2; ///< A(C_n^C) per finger, when evaluated
  MeshOutcome raw;
  MeshOutcome filtered;
  bool evaluated = false;                  ///< both mapped grasps eligible: regions were computed
  /// How far the grasp is from the rim of the seen surface: the smallest
  /// distance (m) from a contact of G^R or G^F (as mapped by eq. (2)) to the
  /// filtered mesh's boundary (its vertices on an edge only one face uses),
  /// in the common frame. 0 when a contact could not be mapped onto one of
  /// the meshes (its normal line reaches no surface there: beyond the seen
  /// surface); Infinity when the filtered mesh has no boundary; unset in
  /// records written before it existed. A
  /// CAD grasp on or near surface no view saw (an object's base) is mapped
  /// onto that rim; results_tables.hpp reports eligibility without such
  /// grasps beside the paper's (TableOneOptions::seen_rim_distance_m).
  std::optional<double> seen_rim_distance_m;
  /// Set for grasps the plain experiment evaluated when
  /// ExperimentConfig::patch is set; unset otherwise.
  std::optional<PatchRecord> patch;

  /// Records sort by (dataset, fingers, index): the order of every output.
  bool operator<(const GraspRecord& other) const;
};

/// One JSON object on one line (no trailing newline); exact round trip of
/// every field (doubles in the shortest form that reads back bit-identical;
/// non-finite ones as the strings "NaN", "Infinity", "-Infinity").
std::string toJsonLine(const GraspRecord& record);
/// Throws InputError naming `source` and `line` (1-based) for malformed input.
GraspRecord fromJsonLine(const std::string& text, const std::string& source = "grasps.jsonl", std::size_t line = 0);

/// Reads a whole grasps.jsonl (blank lines allowed) / writes one atomically.
std::vector<GraspRecord> readGraspRecords(const std::string& path);
void writeGraspRecords(const std::string& path, const std::vector<GraspRecord>& records);

}  // namespace icrkit::eval
