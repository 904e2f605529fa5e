#pragma once
/// \file
/// The multi-point (patch) contact model of the reference ICR library: a
/// finger touching vertex c is modelled by a small patch of surface points
/// around c, every one of which applies its own full-strength wrenches.
///
/// Patch of a centre c: breadth-first search over mesh edges from c, entering
/// only vertices within Euclidean distance r of c (inclusive), i.e. the
/// connected piece of the closed ball around c that holds c. With the border
/// filter (the reference's `filter_patch`) only c and the piece's border
/// vertices (those with a mesh neighbour farther than r from c) are kept.
/// The prototype GWS is the hull of the wrenches of every point of every
/// contact's patch; a finger owns the zones of the hull vertices its patch
/// produced; a vertex v qualifies for finger i when every zone of finger i
/// holds at least one wrench of v's patch (different zones may be held by
/// different points). Every patch point counts at full strength, so epsilon
/// and the regions grow with the mesh density (docs/icr.md).

#include <icrkit/icr/independent_contact_regions.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

namespace icrkit::icr {

struct PatchParameters {
  /// r, metres: patch points lie within this Euclidean distance of the
  /// centre (inclusive). Must be finite and > 0; below the shortest edge
  /// every patch is its centre alone and the model is the single-point one.
  double radius_m = 0.005;
  /// Keep only the centre and the patch's border vertices (the reference
  /// library's `filter_patch`, on in its reference regions); false keeps
  /// every vertex of the connected piece.
  bool filter_border = true;

  /// Throws InputError (source "PatchParameters::radius_m") on a
  /// radius that is not finite or not > 0.
  void validate() const;
};

/// The patch of every vertex of one object for one PatchParameters, built
/// the first time a vertex's patch is asked for and kept for every later
/// grasp. Thread-safe: concurrent grasps may share one instance (each patch
/// is built exactly once, under its own once-flag); the patches do not depend
/// on the order they are built in. Keeps a reference to `object`, which must
/// outlive it.
///
/// Every vertex a patch reaches through mesh edges is a patch point,
/// including excluded ones: a patch is the surface a finger at its centre
/// touches, whatever preselection thinks of the points as centres. Only
/// eligible vertices are centres of regions. An unreferenced vertex has no
/// edges: its patch is itself.
class ContactPatches {
public:
  /// Throws InputError on invalid parameters.
  explicit ContactPatches(const GraspableObject& object, const PatchParameters& params = {});
  ContactPatches(const ContactPatches&) = delete;
  ContactPatches& operator=(const ContactPatches&) = delete;

  /// The (filtered) patch of `centre`: vertex ids, ascending, `centre`
  /// among them. `centre` must be a valid vertex index.
  const std::vector<int>& of(int centre) const;
  /// Builds every patch now, in parallel (TBB); later `of` calls only read.
  void buildAll() const;
  /// How many patches have been built so far.
  std::size_t builtCount() const { return built_.load(std::memory_order_relaxed); }

  const GraspableObject& object() const { return *object_; }
  const PatchParameters& parameters() const { return params_; }

private:
  std::vector<int> build(int centre) const;

  const GraspableObject* object_;
  PatchParameters params_;
  std::unique_ptr<std::once_flag[]> once_;
  mutable std::vector<std::vector<int>> patches_;
  mutable std::atomic<std::size_t> built_{0};
};

/// The patch of `centre` computed directly (no caching): what
/// ContactPatches::of returns. Exposed for tests and one-off queries.
std::vector<int> contactPatch(const GraspableObject& object, int centre, const PatchParameters& params);

/// The GWS of a grasp of patch contacts: the hull of the wrenches of every
/// point of every contact's patch, contact by contact, each patch in
/// ascending vertex order. `finger_of_wrench`, when given, receives the
/// contact index of every wrench (column) the hull was built from.
GraspWrenchSpace patchGraspWrenchSpace(const ContactPatches& patches, const std::vector<int>& contacts,
                                       const ContactModel& model, const HullParameters& hull = {},
                                       std::vector<int>* finger_of_wrench = nullptr);

/// Independent Contact Regions of the patch contact model: the same inputs,
/// checks, errors and result as computeIndependentContactRegions (regions
/// are sorted centre vertex ids; only eligible vertices and the prototype
/// contact join them), with every contact and candidate replaced by its
/// patch in `patches`, which must have been built on `object`'s mesh.
/// `vertices_tested` counts the patch points whose wrenches were computed.
IcrResult computePatchContactRegions(const GraspableObject& object, const ContactPatches& patches,
                                     const std::vector<int>& contacts, const IcrParameters& params = {});

/// The same, from the prototype's patch GWS already built by
/// patchGraspWrenchSpace (with `finger_of_wrench`) on these contacts and
/// `params.hull`: for callers that check the GWS against a task first, so
/// the hull (most of the cost) is built once. `timings.hull_ms` is then 0.
IcrResult computePatchContactRegions(const GraspableObject& object, const ContactPatches& patches,
                                     const std::vector<int>& contacts, const GraspWrenchSpace& prototype_gws,
                                     const std::vector<int>& finger_of_wrench, const IcrParameters& params = {});

}  // namespace icrkit::icr
