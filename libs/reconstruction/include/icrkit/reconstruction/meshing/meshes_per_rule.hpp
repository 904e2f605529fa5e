#pragma once
/// \file
/// One cloud's raw mesh and a filtered mesh per preselection rule, as the
/// sensitivity study (eval/sensitivity_study.hpp) needs them for each noisy
/// sample of a CAD surface.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/ndt/preselection.hpp>
#include <icrkit/reconstruction/meshing/raw_and_filtered_meshes.hpp>

#include <vector>

namespace icrkit::reconstruction {

struct MeshesPerRule {
  TriangleMesh raw;
  std::vector<TriangleMesh> filtered;  ///< filtered[i] for rules[i]
};

/// The cloud's normals are estimated first (its own are dropped: a scan has
/// none), then meshRawAndFiltered runs once and each rule decides the
/// `excluded` flags of a copy of its filtered mesh; with
/// `params.mesh_kept_points_only` each rule's excluded points are left out of
/// its own filtered mesh instead (one meshing per rule, the raw mesh from the
/// first). `params.smoothing.preselection.rule` is replaced by the rules.
MeshesPerRule meshRawAndFilteredPerRule(const PointCloud& cloud, const std::vector<ndt::PreselectionRule>& rules,
                                        RawAndFilteredParameters params);

}  // namespace icrkit::reconstruction
