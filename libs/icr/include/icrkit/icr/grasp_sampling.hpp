#pragma once
/// \file
/// Random force-closure grasps on a GraspableObject.

#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/grasp_wrench_space.hpp>

#include <cstdint>
#include <vector>

namespace icrkit::icr {

struct GraspSamplingParameters {
  std::size_t fingers = 4;
  std::size_t count = 200;              ///< grasps wanted
  std::uint64_t seed = 1;
  double min_epsilon = 0.0;             ///< keep only grasps with epsilon >= this
  std::size_t max_attempts = 1000000;   ///< give up after this many random draws
  HullParameters hull;
};

struct SampledGrasp {
  std::vector<int> contacts;  ///< distinct vertex indices, each used by a face and not excluded
  double epsilon = 0.0;
};

struct GraspSamplingStatistics {
  std::size_t attempts = 0;
  std::size_t rejected_by_precheck = 0;  ///< rejected without building a hull
  std::size_t hulls_built = 0;
  double time_ms = 0.0;
};

/// Draws grasps uniformly over the vertices that a face uses and that are not
/// excluded (deterministic for a seed, whatever the thread count; a vertex no
/// face uses is skipped without consuming a draw, so the grasps are those of
/// the mesh without such vertices, renumbered). Fewer than `count` grasps come back when
/// max_attempts is reached.
std::vector<SampledGrasp> sampleForceClosureGrasps(const GraspableObject& object, const ContactModel& model,
                                                   const GraspSamplingParameters& params,
                                                   GraspSamplingStatistics* statistics = nullptr);

/// Cheap necessary condition for force closure: false proves the wrenches do
/// not positively span R^6 (so no hull is needed); true means "maybe".
bool mayBeForceClosure(const WrenchSet& wrenches);

}  // namespace icrkit::icr
