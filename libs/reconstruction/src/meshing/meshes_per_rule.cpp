#include <icrkit/reconstruction/meshing/meshes_per_rule.hpp>

#include <icrkit/ndt/normal_estimation.hpp>

namespace icrkit::reconstruction {

MeshesPerRule meshRawAndFilteredPerRule(const PointCloud& noisy, const std::vector<ndt::PreselectionRule>& rules,
                                        RawAndFilteredParameters params) {
  PointCloud cloud = noisy;
  cloud.normals.clear();  // the raw mesh gets estimated normals, as a scan would
  ndt::estimateNormals(cloud);
  MeshesPerRule out;
  if (!params.mesh_kept_points_only) {
    RawAndFilteredMeshes meshes = meshRawAndFiltered(cloud, params);
    out.raw = std::move(meshes.raw);
    for (const ndt::PreselectionRule rule : rules) {
      ndt::PreselectionParameters preselection;
      preselection.rule = rule;
      TriangleMesh filtered = meshes.filtered;
      ndt::applyPreselection(filtered.vertices.attributes, filtered.vertexCount(), preselection, "filtered mesh");
      out.filtered.push_back(std::move(filtered));
    }
    return out;
  }
  for (std::size_t r = 0; r < rules.size(); ++r) {
    params.smoothing.preselection.rule = rules[r];
    RawAndFilteredMeshes meshes = meshRawAndFiltered(cloud, params);
    if (r == 0) out.raw = std::move(meshes.raw);
    out.filtered.push_back(std::move(meshes.filtered));
  }
  return out;
}

}  // namespace icrkit::reconstruction
