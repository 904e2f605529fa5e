#include <icrkit/eval/grasp_regions.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/icr/graspable_object.hpp>

namespace icrkit::eval {

GraspRegions regrowRegions(const DatasetMeshes& meshes, const ExperimentConfig& config, const GraspRecord& record) {
  GraspRegions regions;
  if (!record.evaluated) return regions;
  if (!meshes.cad || !meshes.raw || !meshes.filtered)
    throw InputError("grasp regions", record.dataset, "the CAD, raw and filtered meshes are all needed");
  // The experiment's own frame, growth parameters and exclusion: the same
  // regions come back.
  const icr::WrenchFrame frame = commonWrenchFrame(*meshes.cad);
  const icr::IcrParameters params = config.icrParameters(record.tws_radius);
  const auto grow = [&](const TriangleMesh& mesh, std::vector<std::uint8_t> excluded, const std::vector<int>& contacts) {
    const icr::GraspableObject object(mesh, frame, std::move(excluded));
    std::vector<std::vector<int>> out;
    for (const icr::ContactRegion& region : icr::computeIndependentContactRegions(object, contacts, params).regions)
      out.push_back(region.vertices);
    return out;
  };
  regions.cad = grow(*meshes.cad, {}, record.cad_contacts);
  regions.raw = grow(*meshes.raw, {}, record.raw.contacts);
  regions.filtered = grow(*meshes.filtered, config.filteredExclusion(*meshes.filtered), record.filtered.contacts);
  return regions;
}

}  // namespace icrkit::eval
