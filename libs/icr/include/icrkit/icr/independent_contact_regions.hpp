#pragma once
/// \file
/// Independent Contact Regions (Krug et al. 2010): for a force-closure
/// prototype grasp, one region per finger such that any choice of one vertex
/// per region is a grasp whose GWS contains the TWS.

#include <icrkit/icr/conservative_growth.hpp>
#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/recommended_contact.hpp>
#include <icrkit/icr/grasp_wrench_space.hpp>
#include <icrkit/icr/task_wrench_space.hpp>

#include <optional>
#include <vector>

namespace icrkit::icr {

enum class GrowthMode {
  BreadthFirst,  ///< grow over mesh neighbours from the prototype contact; failing vertices are not expanded
  Full           ///< test every vertex of the mesh that a face uses
};

struct IcrParameters {
  ContactModel contact_model;
  /// TWS: a ball of radius alpha * epsilon of the prototype (alpha in
  /// (0, 1]), or of the absolute radius `tws_radius` when that is set
  /// (finite, >= 0); `tws_wrenches`, when set, replaces the ball by their
  /// convex hull.
  double alpha = 0.5;
  std::optional<double> tws_radius;
  std::optional<WrenchSet> tws_wrenches;
  GrowthMode mode = GrowthMode::BreadthFirst;
  HullParameters hull;
  /// When set, regions hold only vertices that keep the guarantee for every
  /// normal and position within their uncertainty bounds
  /// (conservative_growth.hpp); the prototype contact then joins its
  /// region only if it qualifies too, so a region may be empty.
  std::optional<ConservativeGrowth> conservative;
};

struct ContactRegion {
  std::size_t finger = 0;
  int contact = -1;              ///< the prototype contact vertex
  std::vector<int> vertices;     ///< sorted ascending; holds `contact` except under conservative growth
  double area_m2 = 0.0;          ///< A(C_n): triangles whose three vertices are all in the region
  RecommendedContact recommended;  ///< where to aim the finger (recommended_contact.hpp)
};

struct IcrTimings {
  double hull_ms = 0.0;
  double zones_ms = 0.0;
  double growth_ms = 0.0;
  double total_ms = 0.0;
};

struct IcrResult {
  double epsilon = 0.0;
  double lambda_m = 0.0;
  double tws_radius = 0.0;  ///< for a polytope TWS, its largest support over the GWS facet normals
  std::size_t gws_facets = 0;
  std::vector<ContactRegion> regions;  ///< one per finger, in contact order
  std::size_t vertices_tested = 0;     ///< vertices whose wrenches were computed
  IcrTimings timings;
};

/// Regions hold only vertices some face uses and that are not excluded.
/// Throws InputError on fewer than 2 contacts, repeated, out-of-range,
/// excluded or unreferenced (used by no face) contacts, a prototype that is not force closure, alpha outside
/// (0, 1], or a TWS that does not fit inside the GWS.
IcrResult computeIndependentContactRegions(const GraspableObject& object, const std::vector<int>& contacts,
                                           const IcrParameters& params = {});

/// The same from the prototype's GWS already built (graspWrenchSpace on
/// these contacts, params.contact_model and params.hull): for callers that
/// check the hull against a task before growing regions (the planner), so
/// that the hull, most of a small mesh's cost, is built once.
/// `timings.hull_ms` is then 0.
IcrResult computeIndependentContactRegions(const GraspableObject& object, const std::vector<int>& contacts,
                                           const GraspWrenchSpace& prototype_gws, const IcrParameters& params = {});

/// A(C): total area of the faces whose three vertices are all in `region`.
double regionArea(const TriangleMesh& mesh, const std::vector<int>& region);

/// The GWS of a grasp given by vertex indices (no checks beyond range).
GraspWrenchSpace graspWrenchSpace(const GraspableObject& object, const std::vector<int>& contacts,
                                  const ContactModel& model, const HullParameters& hull = {});

}  // namespace icrkit::icr
