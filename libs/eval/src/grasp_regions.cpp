#include <icrkit/eval/grasp_regions.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/icr/graspable_object.hpp>

namespace icrkit::eval {

GraspRegions regrowRegions(const DatasetMeshes& meshes, const ExperimentConfig& config, const GraspRecord& record) {
  GraspRegions regions;
  if (!record.evaluated) return regions;
  if (!meshes.cad || !meshes.raw || !meshes.filtered)
    throw InputError("grasp regions", record.dataset, "the CAD, raw and filtered meshes are all needed");
  const icr::WrenchFrame frame = icr::makeWrenchFrame(meshes.cad->vertices.positions, icr::TorqueReference::Centroid);
  icr::IcrParameters params;
  params.contact_model = config.contactModel();
  params.tws_radius = record.tws_radius;
  params.mode = config.growth;
  const auto grow = [&](const TriangleMesh& mesh, std::vector<std::uint8_t> excluded, const std::vector<int>& contacts) {
    const icr::GraspableObject object(mesh, frame, std::move(excluded));
    std::vector<std::vector<int>> out;
    for (const icr::ContactRegion& region : icr::computeIndependentContactRegions(object, contacts, params).regions)
      out.push_back(region.vertices);
    return out;
  };
  regions.cad = grow(*meshes.cad, {}, record.cad_contacts);
  regions.raw = grow(*meshes.raw, {}, record.raw.contacts);
  regions.filtered = grow(*meshes.filtered,
                          config.preselection ? icr::exclusionMaskOf(*meshes.filtered) : std::vector<std::uint8_t>{},
                          record.filtered.contacts);
  return regions;
}

}  // namespace icrkit::eval
